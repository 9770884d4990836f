// Every instruction of the ISA table, assembled from text and compared with a word
// built here field by field from spec/isa.toml's encoding (not by isa::encode).
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>

#include <fmt/format.h>

#include "isa/instruction.hpp"
#include "memory_sources.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa::test {
namespace {

namespace si = spec::isa;

void put(std::uint64_t& word, si::Field f, std::uint64_t value) {
  ASSERT_LT(value, std::uint64_t{1} << f.width) << "test value does not fit field at bit " << f.lsb;
  word |= value << f.lsb;
}

// One operand written in text and its fields. The swizzles are worked out by hand:
// lane i of the result reads source lane (swizzle >> 2i) & 3, x=0 y=1 z=2 w=3.
struct Case {
  std::string text;
  std::uint64_t word = 0;
};

Case instruction_case(const InsnSpec& spec) {
  const bool mods = spec.float_modifiers;  // all float-modifier instructions are format R
  Case c;
  c.text = std::string(spec.mnemonic);
  put(c.word, si::kOpcodeField, static_cast<std::uint64_t>(spec.opcode));
  for (int k = 0; k < spec.operand_count; ++k) {
    c.text += k == 0 ? " " : ", ";
    switch (spec.operands[static_cast<std::size_t>(k)]) {
      case Operand::kD:  // r5.xzw: lanes 0, 2, 3
        c.text += "r5.xzw";
        put(c.word, si::kDstField, 5);
        put(c.word, si::kWmaskField, 0b1101);
        break;
      case Operand::kA:  // .wzyx reverses: lanes 3,2,1,0 -> 0b00'01'10'11
        c.text += mods ? "-|r12|.wzyx" : "r12.wzyx";
        put(c.word, si::kARegField, 12);
        put(c.word, si::kASwizzleField, 0x1b);
        if (mods) {
          put(c.word, si::kANegField, 1);
          put(c.word, si::kAAbsField, 1);
        }
        break;
      case Operand::kB:  // .y = yyyy -> 0b01'01'01'01
        c.text += mods ? "|r33|.y" : "r33.y";
        put(c.word, si::kBRegField, 33);
        put(c.word, si::kBSwizzleField, 0x55);
        if (mods) put(c.word, si::kBAbsField, 1);
        break;
      case Operand::kC:  // .zw = zwww -> 0b11'11'11'10
        c.text += mods ? "-r63.zw" : "r63.zw";
        put(c.word, si::kCRegField, 63);
        put(c.word, si::kCSwizzleField, 0xfe);
        if (mods) put(c.word, si::kCNegField, 1);
        break;
      case Operand::kImm:
        c.text += "-5";
        put(c.word, si::kImmField, 0xfffffffb);
        break;
      case Operand::kFimm:  // 1.5 = 0x3fc00000 in IEEE binary32
        c.text += "1.5";
        put(c.word, si::kImmField, 0x3fc00000);
        break;
      case Operand::kMem:  // [r7.z + 0x20]: base lane z (zzzz = 0b10'10'10'10), offset 32
        c.text += "[r7.z + 0x20]";
        put(c.word, si::kARegField, 7);
        put(c.word, si::kASwizzleField, 0xaa);
        put(c.word, si::kImmField, 32);
        break;
      case Operand::kTarget:
        c.text += "123";
        put(c.word, si::kImmField, 123);
        break;
      case Operand::kSr:  // spec/isa.toml: launch is special register 1
        c.text += "launch";
        put(c.word, si::kImmField, 1);
        break;
    }
  }
  return c;
}

TEST(AsmEncoding, EveryInstructionOfTheTableAssemblesToItsFields) {
  std::string source;
  std::vector<Case> cases;
  for (const InsnSpec& spec : si::kInsns) {
    cases.push_back(instruction_case(spec));
    source += cases.back().text + "\n";
  }
  const Firmware fw = assemble_text(source);
  ASSERT_EQ(fw.code.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(fw.code[i], cases[i].word) << cases[i].text << fmt::format(": got {:#018x}, expected {:#018x}",
                                                                           fw.code[i], cases[i].word);
  }
}

TEST(AsmEncoding, TableHasTheDocumentedSixtyFourInstructionsWithDistinctOpcodes) {
  std::set<Opcode> opcodes;
  for (const InsnSpec& spec : si::kInsns) opcodes.insert(spec.opcode);
  EXPECT_EQ(si::kInsns.size(), 64u);
  EXPECT_EQ(opcodes.size(), si::kInsns.size());
}

TEST(AsmEncoding, DefaultsAreAllLanesAndIdentitySwizzle) {
  // mov r1, r2: wmask 0xf, swizzle x y z w = 0b11'10'01'00 = 0xe4.
  std::uint64_t w = 0;
  put(w, si::kOpcodeField, 0x01);
  put(w, si::kDstField, 1);
  put(w, si::kWmaskField, 0xf);
  put(w, si::kARegField, 2);
  put(w, si::kASwizzleField, 0xe4);
  EXPECT_EQ(assemble_text("mov r1, r2").code.at(0), w);
}

TEST(AsmEncoding, WriteMaskNoneAndEverySwizzleLength) {
  const Firmware fw = assemble_text(
      "mov r0.none, r1.x\n"      // xxxx = 0x00
      "mov r0.w, r1.xy\n"        // xyyy = 0b01'01'01'00 = 0x54
      "mov r0.yz, r1.xyz\n"      // xyzz = 0b10'10'01'00 = 0xa4
      "mov r0.xyzw, r1.wwwx\n"   // wwwx = 0b00'11'11'11 = 0x3f
      "mov r0, -r1\n"            // neg, identity
      "mov r0, |r1| .x\n");      // a suffix apart from its register still applies
  auto fields = [](std::uint64_t word, si::Field f) { return (word >> f.lsb) & ((1ull << f.width) - 1); };
  EXPECT_EQ(fields(fw.code[0], si::kWmaskField), 0u);
  EXPECT_EQ(fields(fw.code[0], si::kASwizzleField), 0x00u);
  EXPECT_EQ(fields(fw.code[1], si::kWmaskField), 0b1000u);
  EXPECT_EQ(fields(fw.code[1], si::kASwizzleField), 0x54u);
  EXPECT_EQ(fields(fw.code[2], si::kWmaskField), 0b0110u);
  EXPECT_EQ(fields(fw.code[2], si::kASwizzleField), 0xa4u);
  EXPECT_EQ(fields(fw.code[3], si::kWmaskField), 0xfu);
  EXPECT_EQ(fields(fw.code[3], si::kASwizzleField), 0x3fu);
  EXPECT_EQ(fields(fw.code[4], si::kANegField), 1u);
  EXPECT_EQ(fields(fw.code[4], si::kAAbsField), 0u);
  EXPECT_EQ(fields(fw.code[5], si::kAAbsField), 1u);
  EXPECT_EQ(fields(fw.code[5], si::kASwizzleField), 0x00u);
}

TEST(AsmEncoding, MemoryOffsetsAreTwosComplementAndSignedAsInC) {
  const Firmware fw = assemble_text(
      "ld r1, [r2]\n"
      "ld r1, [r2 - 4]\n"
      "ld r1, [r2 - 4 + 2]\n"       // C reading: r2 + (-4) + 2
      "ld r1, [r2 + 0xffffffff]\n"
      "ld r1, [r2 - 0x80000000]\n");
  auto imm = [](std::uint64_t word) { return static_cast<std::uint32_t>(word >> si::kImmField.lsb); };
  EXPECT_EQ(imm(fw.code[0]), 0u);
  EXPECT_EQ(imm(fw.code[1]), 0xfffffffcu);
  EXPECT_EQ(imm(fw.code[2]), 0xfffffffeu);
  EXPECT_EQ(imm(fw.code[3]), 0xffffffffu);
  EXPECT_EQ(imm(fw.code[4]), 0x80000000u);
}

TEST(AsmEncoding, SpecialRegistersByNameOrNumber) {
  // spec/isa.toml: pixel 0, launch 1, thread 2, params 3.
  const Firmware fw = assemble_text("rdsr r1, pixel\nrdsr r1, thread\nrdsr r1, params\nrdsr r1, 7\n");
  auto imm = [](std::uint64_t word) { return static_cast<std::uint32_t>(word >> si::kImmField.lsb); };
  EXPECT_EQ(imm(fw.code[0]), 0u);
  EXPECT_EQ(imm(fw.code[1]), 2u);
  EXPECT_EQ(imm(fw.code[2]), 3u);
  EXPECT_EQ(imm(fw.code[3]), 7u);
}

}  // namespace
}  // namespace rpu::isa::test
