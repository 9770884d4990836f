#include "isa/instruction.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include <fmt/format.h>

namespace rpu::isa {

namespace si = spec::isa;

namespace {

std::uint64_t get(std::uint64_t word, si::Field f) {
  return (word >> f.lsb) & ((std::uint64_t{1} << f.width) - 1);
}

void put(std::uint64_t& word, si::Field f, std::uint64_t value) {
  const std::uint64_t mask = ((std::uint64_t{1} << f.width) - 1) << f.lsb;
  word = (word & ~mask) | ((value << f.lsb) & mask);
}

constexpr std::array<si::Field, 3> kRegField{si::kARegField, si::kBRegField, si::kCRegField};
constexpr std::array<si::Field, 3> kSwizzleField{si::kASwizzleField, si::kBSwizzleField, si::kCSwizzleField};
constexpr std::array<si::Field, 3> kNegField{si::kANegField, si::kBNegField, si::kCNegField};

constexpr char kLane[] = "xyzw";

std::string mask_text(std::uint8_t wmask) {
  if (wmask == kAllLanes) return "";
  std::string s = ".";
  for (int i = 0; i < 4; ++i) {
    if (wmask >> i & 1) s += kLane[i];
  }
  return s == "." ? ".none" : s;
}

// The shortest swizzle text that reads back to the same swizzle: trailing repeats of
// the last lane are implied (".x" = xxxx, ".xy" = xyyy).
std::string swizzle_text(std::uint8_t swizzle) {
  if (swizzle == kIdentitySwizzle) return "";
  int n = 4;
  while (n > 1 && ((swizzle >> 2 * (n - 1)) & 3) == ((swizzle >> 2 * (n - 2)) & 3)) --n;
  std::string s = ".";
  for (int i = 0; i < n; ++i) s += kLane[(swizzle >> 2 * i) & 3];
  return s;
}

std::string imm_text(std::uint32_t imm) {
  const auto v = static_cast<std::int32_t>(imm);
  if (v >= -65536 && v <= 65536) return fmt::format("{}", v);
  return fmt::format("{:#010x}", imm);
}

// A float immediate prints as a decimal that reads back to the same fp32 bits; NaNs
// (whose payload a decimal cannot carry) and everything else as raw hex bits.
std::string fimm_text(std::uint32_t imm) {
  const float f = std::bit_cast<float>(imm);
  if (std::isnan(f)) return fmt::format("{:#010x}", imm);
  if (std::isinf(f)) return f < 0 ? "-inf" : "inf";
  std::string s = fmt::format("{}", f);  // shortest round-trip form
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::string destination_text(std::uint8_t reg, std::uint8_t wmask) { return fmt::format("r{}{}", reg, mask_text(wmask)); }

std::string source_text(const Source& s) {
  return fmt::format("{}{}r{}{}{}", s.neg ? "-" : "", s.abs ? "|" : "", s.reg, s.abs ? "|" : "",
                     swizzle_text(s.swizzle));
}

const InsnSpec* find_insn(std::string_view mnemonic) {
  for (const InsnSpec& s : si::kInsns) {
    if (s.mnemonic == mnemonic) return &s;
  }
  return nullptr;
}

RegisterUse register_use(const Instruction& insn) {
  RegisterUse use;
  const bool store = insn.spec->dst_is_data;
  for (int k = 0; k < insn.spec->operand_count; ++k) {
    switch (insn.spec->operands[static_cast<std::size_t>(k)]) {
      case Operand::kD: (store ? use.data : use.dst) = insn.dst; break;
      case Operand::kA:
      case Operand::kMem: use.src[0] = insn.src[0].reg; break;
      case Operand::kB: use.src[1] = insn.src[1].reg; break;
      case Operand::kC: use.src[2] = insn.src[2].reg; break;
      default: break;
    }
  }
  return use;
}

const spec::isa::SpecialSpec* find_special(std::string_view name) {
  for (const auto& s : si::kSpecials) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::optional<Instruction> decode(std::uint64_t word, std::string* why) {
  const auto opcode = static_cast<Opcode>(get(word, si::kOpcodeField));
  const InsnSpec* spec = find_insn(opcode);
  if (!spec) {
    if (why) *why = fmt::format("unknown opcode {:#04x}", static_cast<unsigned>(opcode));
    return std::nullopt;
  }
  if (const std::uint64_t stray = word & ~spec->used_bits) {
    if (why) {
      *why = fmt::format("{} with bits {:#018x} set that it does not use (unused fields must be zero{})",
                         spec->mnemonic, stray, spec->float_modifiers ? "" : "; no neg/abs modifiers");
    }
    return std::nullopt;
  }
  Instruction insn;
  insn.spec = spec;
  insn.dst = static_cast<std::uint8_t>(get(word, si::kDstField));
  insn.wmask = static_cast<std::uint8_t>(get(word, si::kWmaskField));
  const int sources = spec->format == si::Format::kR ? 3 : 1;
  for (int i = 0; i < sources; ++i) {
    insn.src[i].reg = static_cast<std::uint8_t>(get(word, kRegField[i]));
    insn.src[i].swizzle = static_cast<std::uint8_t>(get(word, kSwizzleField[i]));
    insn.src[i].neg = get(word, kNegField[i]) != 0;
  }
  if (spec->format == si::Format::kR) {
    insn.src[0].abs = get(word, si::kAAbsField) != 0;
    insn.src[1].abs = get(word, si::kBAbsField) != 0;
  } else {
    insn.src[0].neg = false;
    insn.imm = static_cast<std::uint32_t>(get(word, si::kImmField));
  }
  return insn;
}

std::uint64_t encode(const Instruction& insn) {
  std::uint64_t word = 0;
  put(word, si::kOpcodeField, static_cast<std::uint64_t>(insn.spec->opcode));
  put(word, si::kDstField, insn.dst);
  put(word, si::kWmaskField, insn.wmask);
  const int sources = insn.spec->format == si::Format::kR ? 3 : 1;
  for (int i = 0; i < sources; ++i) {
    put(word, kRegField[i], insn.src[i].reg);
    put(word, kSwizzleField[i], insn.src[i].swizzle);
  }
  if (insn.spec->format == si::Format::kR) {
    for (int i = 0; i < 3; ++i) put(word, kNegField[i], insn.src[i].neg);
    put(word, si::kAAbsField, insn.src[0].abs);
    put(word, si::kBAbsField, insn.src[1].abs);
  } else {
    put(word, si::kImmField, insn.imm);
  }
  // Only the fields the instruction uses, so that decode(encode(x)) accepts it.
  return word & insn.spec->used_bits;
}

std::string disassemble(const Instruction& insn) {
  std::string text(insn.spec->mnemonic);
  for (int k = 0; k < insn.spec->operand_count; ++k) {
    text += k == 0 ? " " : ", ";
    switch (insn.spec->operands[k]) {
      case Operand::kD: text += destination_text(insn.dst, insn.wmask); break;
      case Operand::kA: text += source_text(insn.src[0]); break;
      case Operand::kB: text += source_text(insn.src[1]); break;
      case Operand::kC: text += source_text(insn.src[2]); break;
      case Operand::kImm: text += imm_text(insn.imm); break;
      case Operand::kFimm: text += fimm_text(insn.imm); break;
      case Operand::kTarget: text += fmt::format("{}", insn.imm); break;
      case Operand::kMem: {
        const auto offset = static_cast<std::int32_t>(insn.imm);
        const std::string base = source_text(insn.src[0]);
        if (offset > 0) text += fmt::format("[{} + {}]", base, imm_text(insn.imm));
        if (offset < 0) text += fmt::format("[{} - {}]", base, imm_text(0u - insn.imm));
        if (offset == 0) text += fmt::format("[{}]", base);
        break;
      }
      case Operand::kSr: {
        const auto* sr = std::find_if(si::kSpecials.begin(), si::kSpecials.end(),
                                      [&](const si::SpecialSpec& s) { return s.index == static_cast<int>(insn.imm); });
        text += sr != si::kSpecials.end() ? std::string(sr->name) : fmt::format("{}", insn.imm);
        break;
      }
    }
  }
  return text;
}

std::string disassemble(std::uint64_t word) {
  const std::optional<Instruction> insn = decode(word);
  return insn ? disassemble(*insn) : fmt::format(".insn {:#018x}", word);
}

}  // namespace rpu::isa
