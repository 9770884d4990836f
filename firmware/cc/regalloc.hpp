// Register allocation: every virtual register gets lanes of one machine register for the
// whole span in which it is live (liveness by data flow over the code, so loops and
// branches are exact); values live across a trace call are pushed before it and popped
// after it, lane by lane. Where the values do not fit, one not used over a span of code
// that is entered and left at its ends is pushed before the span and popped after it
// (a spill: the memory stack is push/pop only), until they fit.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cc/mir.hpp"

namespace rpu::cc {

struct Location {
  int reg = -1;
  std::array<std::uint8_t, 4> lane{0, 1, 2, 3};  // lane of component j
};

struct SavedRegister {
  int reg = 0;
  std::uint8_t lanes = 0;  // the lanes live across the call (restored by pop with this mask)
};

struct Allocation {
  std::vector<Location> location;                 // per vreg
  std::vector<std::vector<SavedRegister>> saves;  // per instruction (kCall only)
  int registers_used = 0;
  int max_save_bytes = 0;  // the most stack bytes in use at once: spills, and saves at a call
};

// Inserts the spills (kSpill, kReload) into `function`. Throws rpu::Error when it cannot
// fit even so, naming the source line of the value that did not fit.
Allocation allocate(MFunction& function, int registers);

// Every vreg in the register it is pinned to (a scalar in its lane): the allocation of
// code written on machine registers (the trace routines).
Allocation pinned(const MFunction& function);

}  // namespace rpu::cc
