// Assembly text (docs/assembler.md) of an allocated function.
#pragma once

#include <string>

#include "cc/mir.hpp"
#include "cc/regalloc.hpp"

namespace rpu::cc {

// One instruction per line, a comment with the source file and line where it changes.
std::string emit(const MFunction& function, const Allocation& allocation);

}  // namespace rpu::cc
