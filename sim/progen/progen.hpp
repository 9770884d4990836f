#pragma once

#include <cstdint>
#include <functional>

#include "progen/program.hpp"
#include "rpu/spec.hpp"

// Constrained-random shader programs for the shader core (docs/random-programs.md):
// generated from a seed for a hardware configuration, legal and terminating by
// construction, optionally ending in a chosen fault, and shrunk to a small program
// that still shows a failure. What the RTL lockstep co-simulation runs by the
// thousand; `rpu_progen` reproduces one seed.
namespace rpu::progen {

struct Options {
  Machine machine;
  // The class every run must end in: kNone, every thread halts; otherwise the code
  // that faults runs in the lanes of a lane-dependent condition (the first faulting
  // pixel is 0 or 1, so a launch needs at least 2 pixels).
  FaultClass fault = FaultClass::kNone;
  // A watchdog-fault program is run with this limit; the rest of it stays below half.
  std::uint64_t watchdog = 4000;
  // No thread of a program retires more (the fault code of a fault program aside).
  std::uint64_t max_instructions = 2500;
  int max_statements = 10;  // per block; raygen's top level has 1 to 3 times as many
  int max_nesting = 3;      // of if, loop and push/pop regions
  int max_routines = 5;     // functions and hit shaders
  std::uint32_t max_loop_trips = 4;
  int data_words = 64;

  // The machine of a hardware configuration; the rest default.
  static Options for_config(const spec::HardwareConfig& config);
};

// A legal random program; the same seed and options give the same program on every
// host. rpu::Error if the options cannot be met (a fault class the machine cannot have,
// such as a register past the count with 64 registers).
Program generate(std::uint64_t seed, const Options& options);

// Delta debugging (Zeller and Hildebrandt 2002) over the program's structure: removes
// statements (chunks, then single ones), unwraps if/loop/push-pop regions and calls
// (inlining the routine), simplifies calli to call and instructions' operands (identity
// swizzles, no modifiers, all lanes), drops routines nothing calls. Every candidate is
// a program the generator could have made, so it stays legal and terminating; one is
// kept when `still_fails` holds for it. Returns a local minimum: no single such edit
// keeps `still_fails`. Deterministic for a deterministic predicate.
Program shrink(const Program& program, const std::function<bool(const Program&)>& still_fails);

}  // namespace rpu::progen
