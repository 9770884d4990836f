#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rpu/spec.hpp"

// One shader instruction, decoded: the fields of spec/isa.toml's encoding, and the
// table row (mnemonic, operands, class) of its opcode. Encoding, decoding and the
// disassembly syntax (docs/shader-core.md "Assembly") live here so that the assembler,
// the shader core and every tool print the same text.
namespace rpu::isa {

using spec::isa::InsnSpec;
using spec::isa::Opcode;
using spec::isa::Operand;

inline constexpr std::uint8_t kIdentitySwizzle = 0xe4;  // x y z w
inline constexpr std::uint8_t kAllLanes = 0xf;

struct Source {
  std::uint8_t reg = 0;
  std::uint8_t swizzle = 0;  // lane i reads source lane (swizzle >> 2i) & 3
  bool neg = false;
  bool abs = false;  // applied before neg: -|r|
};

struct Instruction {
  const InsnSpec* spec = nullptr;
  std::uint8_t dst = 0;
  std::uint8_t wmask = 0;  // bit i: lane i is written
  std::array<Source, 3> src{};
  std::uint32_t imm = 0;

  Opcode opcode() const { return spec->opcode; }
};

// The registers an instruction reads and writes, from its table row: what the shader
// core checks against the register count and the cycle model's scoreboard tracks.
// st and st1 name the register they store in the dst field: `data`, read, not written.
struct RegisterUse {
  int dst = -1;                       // written, or -1
  int data = -1;                      // read by a store, or -1
  std::array<int, 3> src{-1, -1, -1};  // a, b, c (a also for a memory operand), or -1
};
RegisterUse register_use(const Instruction& insn);

namespace detail {
inline constexpr auto kInsnByOpcode = [] {
  std::array<const InsnSpec*, std::size_t{1} << spec::isa::kOpcodeField.width> table{};
  for (const InsnSpec& s : spec::isa::kInsns) table[static_cast<std::size_t>(s.opcode)] = &s;
  return table;
}();
}  // namespace detail

// The table row of a mnemonic or opcode, or null. By opcode it is an array index, so
// that a compiler may ask for every instruction it makes.
const InsnSpec* find_insn(std::string_view mnemonic);
constexpr const InsnSpec* find_insn(Opcode opcode) {
  const auto i = static_cast<std::size_t>(opcode);
  return i < detail::kInsnByOpcode.size() ? detail::kInsnByOpcode[i] : nullptr;
}
const spec::isa::SpecialSpec* find_special(std::string_view name);

// Fields of an instruction the table says it does not use must be zero, so the word
// is decoded only if it is exactly what encode() would make; otherwise nullopt and
// `why` says which rule it broke.
std::optional<Instruction> decode(std::uint64_t word, std::string* why = nullptr);
std::uint64_t encode(const Instruction& insn);

// Assembly text of a word, e.g. "mad r1.xyz, -r2.x, |r3|, r4"; an illegal word
// prints as ".insn 0x<hex>". The assembler reads back every line it prints.
std::string disassemble(std::uint64_t word);
std::string disassemble(const Instruction& insn);

// The text of a destination register with its write mask (r1.xyz) and of a source
// operand with its modifiers and swizzle (-|r3|.zx), as disassemble prints them.
std::string destination_text(std::uint8_t reg, std::uint8_t wmask);
std::string source_text(const Source& s);

}  // namespace rpu::isa
