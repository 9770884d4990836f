// The firmware as assembly text (docs/assembler.md), for rpu cc --listing: the
// declarations, then every section under its heading, each instruction with its pc in a
// comment and a .loc naming the source file and line where they change. It assembles
// (rpu asm) to the firmware link() makes, line table and all.
#pragma once

#include <string>

#include "cc/machine.hpp"

namespace rpu::cc {

std::string listing(const Program& program);

}  // namespace rpu::cc
