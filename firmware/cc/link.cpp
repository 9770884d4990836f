#include "cc/link.hpp"

#include <map>

#include <fmt/format.h>

#include "cc/listing.hpp"
#include "common/error.hpp"

namespace rpu::cc {

namespace {

[[noreturn]] void internal_error(const Program& program, const std::string& what) {
  throw Error(fmt::format("internal error: {}\n{}", what, listing(program)));
}

}  // namespace

isa::Firmware link(const Program& program) {
  isa::Firmware fw;
  std::map<std::string, std::uint32_t, std::less<>> labels;
  std::uint32_t pc = 0;
  for (const Section& section : program.sections) {
    for (const MachineItem& item : section.items) {
      if (const Label* l = std::get_if<Label>(&item)) {
        if (!labels.emplace(l->name, pc).second) internal_error(program, fmt::format("the label {} twice", l->name));
      } else {
        ++pc;
      }
    }
  }
  fw.code.reserve(pc);
  for (const Section& section : program.sections) {
    for (const MachineItem& item : section.items) {
      if (std::holds_alternative<Label>(item)) continue;
      const MachineInstruction* m = std::get_if<MachineInstruction>(&item);
      const auto pc_here = static_cast<std::uint32_t>(fw.code.size());
      if (m == nullptr) {
        const SourceLocation& where = std::get<IllegalWord>(item).where;
        fw.lines.add(pc_here, where.file, static_cast<std::uint32_t>(where.line));
        fw.code.push_back(0);  // IllegalWord
        continue;
      }
      fw.lines.add(pc_here, m->where.file, static_cast<std::uint32_t>(m->where.line));
      isa::Instruction insn = m->insn;
      if (m->imm.type == Imm::Type::kLabel) {
        const auto it = labels.find(m->imm.label);
        if (it == labels.end()) {
          internal_error(program, fmt::format("no label {} for {}", m->imm.label, insn.spec->mnemonic));
        }
        insn.imm = it->second;
      }
      fw.code.push_back(isa::encode(insn));
    }
  }
  for (const auto& [name, at] : labels) fw.symbols[name] = {isa::Symbol::Kind::kCode, at};
  for (const Declaration& d : program.declarations) {
    fw.symbols[std::string(d.name)] = {isa::Symbol::Kind::kConstant, d.value};
  }
  return fw;
}

}  // namespace rpu::cc
