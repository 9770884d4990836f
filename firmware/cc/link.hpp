// The firmware's words and symbols: every label placed at the index of the instruction
// after it, every instruction encoded by the ISA's encoder (the assembler's), the
// declarations as constants.
#pragma once

#include "cc/machine.hpp"
#include "isa/firmware.hpp"

namespace rpu::cc {

isa::Firmware link(const Program& program);

}  // namespace rpu::cc
