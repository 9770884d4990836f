// The firmware rpu cc makes, as machine instructions: emit.cpp writes them from the
// allocated functions, link.cpp encodes them into an isa::Firmware through the ISA's
// encoder, listing.cpp prints them as assembly text (rpu cc --listing).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "cc/mir.hpp"
#include "isa/instruction.hpp"

namespace rpu::cc {

// An instruction on machine registers. insn.imm holds the immediate's field, but for a
// label, which link() places.
struct MachineInstruction {
  isa::Instruction insn;
  Imm imm;                // the immediate as typed: what the listing prints
  SourceLocation where;   // the source line it was made for (line 0: none)
  std::string_view note;  // the listing's comment on it
};

struct Label {
  std::string name;
  std::string_view note;  // the listing's comment line before it
};

// The all-zero word: no instruction, so that a thread reaching it stops with an
// illegal-instruction fault (at the source line it was made for, if any).
struct IllegalWord {
  SourceLocation where;
};

using MachineItem = std::variant<Label, MachineInstruction, IllegalWord>;

struct Section {
  std::string heading;  // the listing's comment before it
  std::vector<MachineItem> items;
};

// A constant the firmware declares (.equ), which the device checks.
struct Declaration {
  std::string_view name;
  std::uint32_t value = 0;
  std::string_view note;  // the listing's comment line before it
};

struct Program {
  std::string title;  // the listing's first line
  std::vector<Declaration> declarations;
  std::vector<Section> sections;  // in code order: pc 0 is the first section's first instruction
};

}  // namespace rpu::cc
