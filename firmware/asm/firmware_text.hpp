#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "isa/firmware.hpp"

namespace rpu::isa {

// Assembly text of a whole firmware: its .equ constants, .text (one disassembled
// instruction per line, code labels at their pcs, a .loc where the line table changes
// line) and .data (.word, .byte and .space lines, data labels at their addresses).
// Assembling the text gives the same Firmware: code, data, symbols and line table.
std::string firmware_to_text(const Firmware& firmware);

// The .loc directive that gives the following instructions a source line: .loc "file",
// line (the name escaped as the assembler reads strings), or .loc alone for line 0.
std::string source_line_directive(std::string_view file, std::uint32_t line);

}  // namespace rpu::isa
