#pragma once

#include <string>

#include "isa/firmware.hpp"

namespace rpu::isa {

// Assembly text of a whole firmware: its .equ constants, .text (one disassembled
// instruction per line, code labels at their pcs) and .data (.word, .byte and .space
// lines, data labels at their addresses). Assembling the text gives the same
// Firmware: code, data and symbols.
std::string firmware_to_text(const Firmware& firmware);

}  // namespace rpu::isa
