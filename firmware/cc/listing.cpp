#include "cc/listing.hpp"

#include <optional>

#include <fmt/format.h>

#include "asm/firmware_text.hpp"

namespace rpu::cc {

namespace {

std::string imm_text(const Imm& imm) {
  switch (imm.type) {
    case Imm::Type::kBits:
    case Imm::Type::kFloat: return fmt::format("{:#x}", imm.field());
    case Imm::Type::kSpecial:
      for (const spec::isa::SpecialSpec& s : spec::isa::kSpecials) {
        if (s.index == imm.value) return std::string(s.name);
      }
      break;
    case Imm::Type::kSymbol: return std::string(imm.symbol->name);
    case Imm::Type::kLabel: return imm.label;
    case Imm::Type::kNone:
    case Imm::Type::kInteger: break;
  }
  return fmt::format("{}", imm.value);
}

// [r3.x + 16], [r3.x - 4], [r3.x], [r3.z + LAUNCH_MATERIALS_AT]
std::string address_text(const isa::Source& base, const Imm& offset) {
  const std::string r = isa::source_text(base);
  if (offset.type == Imm::Type::kSymbol) return fmt::format("[{} + {}]", r, offset.symbol->name);
  if (offset.value == 0) return fmt::format("[{}]", r);
  return offset.value < 0 ? fmt::format("[{} - {}]", r, -offset.value) : fmt::format("[{} + {}]", r, offset.value);
}

std::string instruction_text(const MachineInstruction& m, std::uint32_t pc) {
  const isa::Instruction& insn = m.insn;
  std::string text = fmt::format("{:<7}", insn.spec->mnemonic);
  for (int k = 0; k < insn.spec->operand_count; ++k) {
    text += k == 0 ? " " : ", ";
    switch (insn.spec->operands[static_cast<std::size_t>(k)]) {
      case isa::Operand::kD: text += isa::destination_text(insn.dst, insn.wmask); break;
      case isa::Operand::kA: text += isa::source_text(insn.src[0]); break;
      case isa::Operand::kB: text += isa::source_text(insn.src[1]); break;
      case isa::Operand::kC: text += isa::source_text(insn.src[2]); break;
      case isa::Operand::kMem: text += address_text(insn.src[0], m.imm); break;
      case isa::Operand::kImm:
      case isa::Operand::kFimm:
      case isa::Operand::kSr:
      case isa::Operand::kTarget: text += imm_text(m.imm); break;
    }
  }
  text.erase(text.find_last_not_of(' ') + 1);
  return m.note.empty() ? fmt::format("{:<39} ; {}", text, pc) : fmt::format("{:<39} ; {}: {}", text, pc, m.note);
}

}  // namespace

std::string listing(const Program& program) {
  std::string out = fmt::format("; {}\n", program.title);
  for (const Declaration& d : program.declarations) {
    if (!d.note.empty()) out += fmt::format("; {}\n", d.note);
    out += fmt::format(".equ {}, {}\n", d.name, d.value);
  }
  out += ".text\n";
  // A .loc where the source line changes (the first instruction's too, even without a
  // line), so that the listing assembles to the firmware with its line table.
  std::optional<SourceLocation> last;
  std::uint32_t pc = 0;
  for (const Section& section : program.sections) {
    out += fmt::format("\n; {}\n", section.heading);
    for (const MachineItem& item : section.items) {
      if (const Label* l = std::get_if<Label>(&item)) {
        if (!l->note.empty()) out += fmt::format("; {}\n", l->note);
        out += l->name + ":\n";
        continue;
      }
      const MachineInstruction* m = std::get_if<MachineInstruction>(&item);
      const SourceLocation where = m ? m->where : std::get<IllegalWord>(item).where;
      const auto line = static_cast<std::uint32_t>(where.line);
      if (!last || line != static_cast<std::uint32_t>(last->line) || (line > 0 && where.file != last->file)) {
        out += fmt::format("        {}\n", isa::source_line_directive(where.file, line));
        last = where;
      }
      out += m ? fmt::format("        {}\n", instruction_text(*m, pc)) : fmt::format("        {:<39} ; {}\n", ".insn 0", pc);
      ++pc;
    }
  }
  return out;
}

}  // namespace rpu::cc
