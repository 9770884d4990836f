// The firmware as assembly text (docs/assembler.md), for rpu cc --listing: the
// declarations, then every section under its heading, each instruction with a comment
// naming the source file and line where they change. It assembles (rpu asm) to the
// firmware link() makes.
#pragma once

#include <string>

#include "cc/machine.hpp"

namespace rpu::cc {

std::string listing(const Program& program);

}  // namespace rpu::cc
