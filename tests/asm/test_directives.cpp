// Labels, .equ, expressions, data directives, float literals, .include, the listing
// and firmware text: what a program is made of besides instructions.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "asm/firmware_text.hpp"
#include "memory_sources.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa::test {
namespace {

namespace si = spec::isa;
constexpr std::uint32_t kData = spec::memory::kDeviceDataBase;

std::uint32_t imm(std::uint64_t word) { return static_cast<std::uint32_t>(word >> si::kImmField.lsb); }

std::uint32_t constant(const Firmware& fw, const std::string& name) {
  const auto it = fw.symbols.find(name);
  if (it == fw.symbols.end()) {
    ADD_FAILURE() << "no symbol " << name;
    return 0;
  }
  EXPECT_EQ(it->second.kind, Symbol::Kind::kConstant) << name;
  return it->second.value;
}

TEST(AsmExpressions, FollowCPrecedenceAndTwosComplement) {
  // The expected values are the C++ compiler's reading of the same expressions.
  const Firmware fw = assemble_text(
      ".equ A, 1 + 2 * 3\n"
      ".equ B, (1 + 2) * 3\n"
      ".equ C, 1 << 2 + 1\n"
      ".equ D, 6 & 3 | 8 ^ 1\n"
      ".equ E, -7 / 2\n"
      ".equ F, -7 % 2\n"
      ".equ G, ~0\n"
      ".equ H, 0b101 + 0x10 + 010\n"
      ".equ I, -(1 << 31)\n"
      ".equ J, 0xffffffff\n"
      ".equ K, 1 << 40 >> 20\n"
      ".equ L, -8 >> 1\n"
      ".equ M, +5 - -3\n");
  EXPECT_EQ(constant(fw, "A"), static_cast<std::uint32_t>(1 + 2 * 3));
  EXPECT_EQ(constant(fw, "B"), static_cast<std::uint32_t>((1 + 2) * 3));
  EXPECT_EQ(constant(fw, "C"), static_cast<std::uint32_t>(1 << (2 + 1)));
  EXPECT_EQ(constant(fw, "D"), static_cast<std::uint32_t>((6 & 3) | (8 ^ 1)));
  EXPECT_EQ(constant(fw, "E"), static_cast<std::uint32_t>(-7 / 2));
  EXPECT_EQ(constant(fw, "F"), static_cast<std::uint32_t>(-7 % 2));
  EXPECT_EQ(constant(fw, "G"), 0xffffffffu);
  EXPECT_EQ(constant(fw, "H"), 5u + 16u + 10u);  // 010 is decimal ten: no octal
  EXPECT_EQ(constant(fw, "I"), 0x80000000u);
  EXPECT_EQ(constant(fw, "J"), 0xffffffffu);
  EXPECT_EQ(constant(fw, "K"), 1u << 20);
  EXPECT_EQ(constant(fw, "L"), static_cast<std::uint32_t>(-4));
  EXPECT_EQ(constant(fw, "M"), 8u);
}

TEST(AsmExpressions, ConstantsMayBeUsedBeforeTheirDefinition) {
  const Firmware fw = assemble_text(
      "li r1, LATER * 2\n"
      ".equ LATER, EVEN_LATER + 1\n"
      ".equ EVEN_LATER, 20\n");
  EXPECT_EQ(imm(fw.code[0]), 42u);
  EXPECT_EQ(constant(fw, "LATER"), 21u);
}

TEST(AsmExpressions, MemoryMapSymbolsArePredefined) {
  const Firmware fw = assemble_text("li r1, LAUNCH_WIDTH_AT\nli r2, DEVICE_LAUNCH_BASE + LAUNCH_SPP_AT\n");
  // spec/memory_map.toml: [launch] width_at = 0, spp_at = 8; launch_base 0x40000000.
  EXPECT_EQ(imm(fw.code[0]), 0u);
  EXPECT_EQ(imm(fw.code[1]), 0x40000008u);
}

TEST(AsmLabels, CodeLabelsAreInstructionIndicesAndDataLabelsAddresses) {
  const Firmware fw = assemble_text(
      "start: bra end\n"
      "  ; a comment line\n"
      "middle:\n"
      "  li r1, table\n"
      "  li r2, last - table\n"
      "end: halt\n"
      ".data\n"
      "table: .word 1, 2\n"
      "last: .word 3\n"
      "after:\n");
  EXPECT_EQ(imm(fw.code[0]), 3u);
  EXPECT_EQ(imm(fw.code[1]), kData);
  EXPECT_EQ(imm(fw.code[2]), 8u);
  ASSERT_EQ(fw.symbols.size(), 6u);
  EXPECT_EQ(fw.symbols.at("start").kind, Symbol::Kind::kCode);
  EXPECT_EQ(fw.symbols.at("start").value, 0u);
  EXPECT_EQ(fw.symbols.at("middle").value, 1u);
  EXPECT_EQ(fw.symbols.at("end").value, 3u);
  EXPECT_EQ(fw.symbols.at("table").kind, Symbol::Kind::kData);
  EXPECT_EQ(fw.symbols.at("table").value, kData);
  EXPECT_EQ(fw.symbols.at("last").value, kData + 8);
  EXPECT_EQ(fw.symbols.at("after").value, kData + 12);
}

TEST(AsmLabels, SeveralLabelsOnALineAndDottedNames) {
  const Firmware fw = assemble_text("a: .b_1: c.d: halt\n");
  EXPECT_EQ(fw.code.size(), 1u);
  for (const char* name : {"a", ".b_1", "c.d"}) EXPECT_EQ(fw.symbols.at(name).value, 0u) << name;
}

TEST(AsmData, WordByteFloatSpaceAndAlignLayBytesLittleEndian) {
  const Firmware fw = assemble_text(
      ".data\n"
      ".word 0x11223344, -1\n"
      ".byte 1, -2, 255\n"
      ".align 4\n"
      "f: .float 1.0, -2.5\n"
      ".space 3\n"
      "b: .byte 7\n"
      ".align 8\n"
      "e:\n");
  const std::vector<std::uint8_t> expected{
      0x44, 0x33, 0x22, 0x11, 0xff, 0xff, 0xff, 0xff,  // .word
      0x01, 0xfe, 0xff, 0x00,                          // .byte, then .align 4 pads one byte
      0x00, 0x00, 0x80, 0x3f,                          // 1.0f = 0x3f800000
      0x00, 0x00, 0x20, 0xc0,                          // -2.5f = 0xc0200000
      0x00, 0x00, 0x00,                                // .space 3
      0x07,                                            // b
  };
  EXPECT_EQ(fw.data, expected);
  EXPECT_EQ(fw.symbols.at("f").value, kData + 12);
  EXPECT_EQ(fw.symbols.at("b").value, kData + 23);
  EXPECT_EQ(fw.symbols.at("e").value, kData + 24);  // .align 8 at 24 adds nothing
}

TEST(AsmData, SectionsSwitchBackAndForth) {
  const Firmware fw = assemble_text(".data\nx: .word 5\n.text\nli r1, x\n.data\ny: .word 6\n.text\nhalt\n");
  EXPECT_EQ(fw.code.size(), 2u);
  EXPECT_EQ(fw.data.size(), 8u);
  EXPECT_EQ(imm(fw.code[0]), kData);
  EXPECT_EQ(fw.symbols.at("y").value, kData + 4);
}

TEST(AsmData, RawInsnEmitsAnyWord) {
  const Firmware fw = assemble_text(".insn 0xffffffffffffffff\n.insn 0\n.insn 0x123456789abcdef0\n");
  EXPECT_EQ(fw.code, (std::vector<std::uint64_t>{~0ull, 0, 0x123456789abcdef0ull}));
}

TEST(AsmFloats, DecimalLiteralsRoundToNearestFp32) {
  const Firmware fw = assemble_text(
      "lif r1, 1.5\n"
      "lif r1, -2e-3\n"
      "lif r1, inf\n"
      "lif r1, -inf\n"
      "lif r1, nan\n"
      "lif r1, 0x7f800001\n"
      "lif r1, 1e-45\n"           // the smallest subnormal
      "lif r1, 3.4028235e38\n"    // the largest finite
      "lif r1, 0.1\n"
      "lif r1, -0.0\n"
      "lif r1, 16777217\n");      // 2^24 + 1 rounds to even: 2^24
  const std::vector<std::uint32_t> expected{
      std::bit_cast<std::uint32_t>(1.5f), std::bit_cast<std::uint32_t>(-2e-3f), 0x7f800000, 0xff800000, 0x7fc00000,
      0x7f800001, 0x00000001, 0x7f7fffff, std::bit_cast<std::uint32_t>(0.1f), 0x80000000, 0x4b800000};
  ASSERT_EQ(fw.code.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(imm(fw.code[i]), expected[i]) << "line " << i + 1;
}

TEST(AsmInclude, PathsAreRelativeToTheIncludingFile) {
  MemorySources sources;
  sources.files["src/main.s"] = ".include \"lib/a.s\"\nbra helper\n";
  sources.files["src/lib/a.s"] = ".include \"../common/b.s\"\nhelper: li r1, B\n";
  sources.files["src/common/b.s"] = ".equ B, 9\n";
  const Firmware fw = sources.assemble("src/main.s");
  EXPECT_EQ(sources.requested, (std::vector<std::string>{"src/main.s", "src/lib/a.s", "src/common/b.s"}));
  ASSERT_EQ(fw.code.size(), 2u);
  EXPECT_EQ(imm(fw.code[0]), 9u);
  EXPECT_EQ(imm(fw.code[1]), 0u);
}

TEST(AsmInclude, SameFileTwiceWithoutCycleIsFine) {
  MemorySources sources;
  sources.files["main.s"] = ".include \"x.s\"\n.include \"x.s\"\n";
  sources.files["x.s"] = "halt\n";
  EXPECT_EQ(sources.assemble().code.size(), 2u);
}

// The line table: each instruction's own file:line, or what a .loc in its file set.
TEST(AsmLines, EachInstructionHasItsLineOrTheOneALocSets) {
  MemorySources sources;
  sources.files["main.s"] =
      "halt\n"                              // pc 0: main.s:1
      ".loc \"shade.rchit\", 12\n"
      "halt\n"                              // pc 1: shade.rchit:12
      ".insn 0\n"                           // pc 2: shade.rchit:12
      ".include \"lib.s\"\n"                // pc 3: lib.s:1, its own lines
      "halt\n"                              // pc 4: shade.rchit:12 again
      ".loc\n"
      "halt\n";                             // pc 5: none
  sources.files["lib.s"] = "halt\n";
  const Firmware fw = sources.assemble();
  ASSERT_EQ(fw.code.size(), 6u);
  const std::vector<std::optional<std::string>> expected{"main.s:1", "shade.rchit:12", "shade.rchit:12",
                                                         "lib.s:1",  "shade.rchit:12", std::nullopt};
  for (std::uint32_t pc = 0; pc < fw.code.size(); ++pc) EXPECT_EQ(fw.lines.where(pc), expected[pc]) << "pc " << pc;
  // Canonical: one run per change of line, files in the order the runs name them.
  EXPECT_EQ(fw.lines.files, (std::vector<std::string>{"main.s", "shade.rchit", "lib.s"}));
  EXPECT_EQ(fw.lines.runs.size(), 5u);
}

TEST(AsmListing, NamesPcWordAndSourceLine) {
  MemorySources sources;
  sources.files["main.s"] = "  halt   \n.data\n.word 7\n";
  const Assembly a = assemble_with_listing("main.s", sources.loader());
  ASSERT_EQ(a.listing.size(), 2u);
  EXPECT_TRUE(a.listing[0].code);
  EXPECT_EQ(a.listing[0].line, 1);
  EXPECT_EQ(a.listing[0].text, "  halt");
  EXPECT_FALSE(a.listing[1].code);
  EXPECT_EQ(a.listing[1].address, kData);
  EXPECT_EQ(a.listing[1].bytes, 4u);
  const std::string text = format_listing(a);
  // halt is opcode 0x56 with every other field zero (spec/isa.toml).
  EXPECT_NE(text.find("       0  0000000000000056  main.s:1"), std::string::npos) << text;
  EXPECT_NE(text.find("50000000         (4 bytes)  main.s:3"), std::string::npos) << text;
}

TEST(AsmFirmwareText, ReassemblesToTheSameFirmware) {
  const Firmware fw = assemble_text(
      ".equ SIZE, 0x20\n"
      ".equ NEG, -3\n"
      "main: li r1, SIZE\n"
      ".loc \"a \\\"quoted\\\" name.rchit\", 40\n"
      "loop: bnz r1.y, loop\n"
      ".insn 0xdeadbeefdeadbeef\n"
      "end:\n"
      ".data\n"
      "odd: .byte 1, 2, 3\n"
      "w: .word 0x01020304, 0\n"
      "zeros: .space 40\n"
      ".word 9\n"
      "tail: .byte 0, 5\n"
      "last:\n");
  const std::string text = firmware_to_text(fw);
  const Firmware again = assemble_text(text);
  EXPECT_EQ(again.code, fw.code) << text;
  EXPECT_EQ(again.lines, fw.lines) << text;
  EXPECT_EQ(fw.lines.where(1), "a \"quoted\" name.rchit:40");
  EXPECT_EQ(again.data, fw.data) << text;
  ASSERT_EQ(again.symbols.size(), fw.symbols.size()) << text;
  for (const auto& [name, symbol] : fw.symbols) {
    ASSERT_TRUE(again.symbols.contains(name)) << name;
    EXPECT_EQ(again.symbols.at(name).kind, symbol.kind) << name;
    EXPECT_EQ(again.symbols.at(name).value, symbol.value) << name;
  }
  EXPECT_NE(text.find(".space 40"), std::string::npos) << text;
}

}  // namespace
}  // namespace rpu::isa::test
