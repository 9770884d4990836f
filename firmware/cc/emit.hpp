// Machine code of an allocated function: every instruction of the machine IR on the
// machine registers and lanes the allocation gave its vregs, with the pushes and pops
// around calls and spills.
#pragma once

#include <vector>

#include "cc/machine.hpp"
#include "cc/mir.hpp"
#include "cc/regalloc.hpp"

namespace rpu::cc {

std::vector<MachineItem> emit(const MFunction& function, const Allocation& allocation);

}  // namespace rpu::cc
