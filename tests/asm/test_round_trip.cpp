// assemble(disassemble(w)) == w: random valid instructions built from the ISA table,
// exhaustive swizzles and masks, and arbitrary (mostly illegal) words via .insn.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "isa/instruction.hpp"
#include "memory_sources.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa::test {
namespace {

namespace si = spec::isa;

// Immediates that exercise the printer's cases: decimal up to +-65536, hex beyond,
// the 32-bit extremes, and uniformly random bits.
std::uint32_t random_imm(std::mt19937_64& rng) {
  static constexpr std::uint32_t kEdges[] = {0,          1,          65535,      65536,      65537,      0xffff0000,
                                             0xfffeffff, 0x7fffffff, 0x80000000, 0x80000001, 0xffffffff, 0xfffffffe};
  switch (rng() % 3) {
    case 0: return kEdges[rng() % std::size(kEdges)];
    case 1: return static_cast<std::uint32_t>(static_cast<std::int32_t>(rng() % 200001) - 100000);
    default: return static_cast<std::uint32_t>(rng());
  }
}

// fp32 bit patterns: zeros, subnormals, infinities, NaNs with payloads, round numbers
// and random bits.
std::uint32_t random_float_bits(std::mt19937_64& rng) {
  static constexpr std::uint32_t kEdges[] = {0x00000000, 0x80000000, 0x00000001, 0x807fffff, 0x00800000,
                                             0x7f7fffff, 0xff7fffff, 0x7f800000, 0xff800000, 0x7fc00000,
                                             0xffc00000, 0x7f800001, 0x7fffffff, 0x3f800000, 0x3dcccccd};
  switch (rng() % 4) {
    case 0: return kEdges[rng() % std::size(kEdges)];
    case 1: return std::bit_cast<std::uint32_t>(static_cast<float>(static_cast<int>(rng() % 20001) - 10000) / 64.0f);
    case 2: return static_cast<std::uint32_t>(rng()) & 0x807fffff;  // subnormal or zero
    default: return static_cast<std::uint32_t>(rng());
  }
}

Source random_source(std::mt19937_64& rng, bool neg, bool abs) {
  Source s;
  s.reg = static_cast<std::uint8_t>(rng() % (1u << si::kARegField.width));
  s.swizzle = static_cast<std::uint8_t>(rng());
  s.neg = neg && (rng() & 1);
  s.abs = abs && (rng() & 1);
  return s;
}

// A random instruction of the table with every field it uses random.
Instruction random_instruction(std::mt19937_64& rng) {
  Instruction insn;
  insn.spec = &si::kInsns[rng() % si::kInsns.size()];
  const bool mods = insn.spec->float_modifiers && insn.spec->format == si::Format::kR;
  for (int k = 0; k < insn.spec->operand_count; ++k) {
    switch (insn.spec->operands[static_cast<std::size_t>(k)]) {
      case Operand::kD:
        insn.dst = static_cast<std::uint8_t>(rng() % (1u << si::kDstField.width));
        insn.wmask = static_cast<std::uint8_t>(rng() % 16);
        break;
      case Operand::kA: insn.src[0] = random_source(rng, mods, mods); break;
      case Operand::kB: insn.src[1] = random_source(rng, mods, mods); break;
      case Operand::kC: insn.src[2] = random_source(rng, mods, false); break;
      case Operand::kMem:
        insn.src[0] = random_source(rng, false, false);
        insn.imm = random_imm(rng);
        break;
      case Operand::kFimm: insn.imm = random_float_bits(rng); break;
      case Operand::kSr: insn.imm = rng() & 1 ? static_cast<std::uint32_t>(rng() % 6) : random_imm(rng); break;
      case Operand::kImm:
      case Operand::kTarget: insn.imm = random_imm(rng); break;
    }
  }
  return insn;
}

// Assembles the disassembly of `words`, one per line, and compares word by word.
void expect_round_trip(const std::vector<std::uint64_t>& words) {
  std::string source;
  std::vector<std::string> lines;
  for (const std::uint64_t w : words) {
    lines.push_back(disassemble(w));
    source += lines.back() + "\n";
  }
  Firmware fw;
  try {
    fw = assemble_text(source);
  } catch (const Error& e) {
    FAIL() << e.what();
  }
  ASSERT_EQ(fw.code.size(), words.size());
  int failures = 0;
  for (std::size_t i = 0; i < words.size() && failures < 10; ++i) {
    if (fw.code[i] != words[i]) {
      ++failures;
      ADD_FAILURE() << fmt::format("{:#018x} disassembles to '{}', which assembles to {:#018x}", words[i], lines[i],
                                   fw.code[i]);
    }
  }
}

TEST(AsmRoundTrip, HundredThousandRandomValidInstructions) {
  std::mt19937_64 rng(20050731);
  std::vector<std::uint64_t> words;
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t w = encode(random_instruction(rng));
    ASSERT_TRUE(decode(w).has_value()) << fmt::format("{:#018x}", w);
    words.push_back(w);
  }
  expect_round_trip(words);
}

TEST(AsmRoundTrip, EverySwizzleWithEveryModifierAndEveryMask) {
  const InsnSpec* mad = find_insn("mad");
  ASSERT_NE(mad, nullptr);
  std::vector<std::uint64_t> words;
  for (int swizzle = 0; swizzle < 256; ++swizzle) {
    for (int mod = 0; mod < 4; ++mod) {
      Instruction insn;
      insn.spec = mad;
      insn.dst = 1;
      insn.wmask = static_cast<std::uint8_t>(swizzle % 16);
      for (int i = 0; i < 3; ++i) {
        insn.src[i] = {static_cast<std::uint8_t>(i + 2), static_cast<std::uint8_t>(swizzle), (mod & 1) != 0,
                       i < 2 && (mod & 2) != 0};
      }
      words.push_back(encode(insn));
    }
  }
  expect_round_trip(words);
}

TEST(AsmRoundTrip, ArbitraryWordsIncludingIllegalOnesReadBack) {
  std::mt19937_64 rng(7);
  std::vector<std::uint64_t> words;
  int illegal = 0;
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t w = rng();
    // Half of them one bit away from a valid word: the decoder's stray-bit rule.
    if (i % 2) w = encode(random_instruction(rng)) ^ (std::uint64_t{1} << (rng() % 64));
    illegal += !decode(w).has_value();
    words.push_back(w);
  }
  EXPECT_GT(illegal, 10000);  // the test is about .insn as much as instructions
  expect_round_trip(words);
}

}  // namespace
}  // namespace rpu::isa::test
