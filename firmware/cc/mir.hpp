// The back end's machine IR: RPU instructions over virtual registers of 1 to 4 lanes.
// Lowering (lower.cpp) writes it, the register allocator (regalloc.cpp) places every
// virtual register in lanes of a machine register, and emit.cpp prints assembly.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cc/spirv_module.hpp"

namespace rpu::cc {

// A virtual register: `width` lanes. A vector (width >= 2) lives in lanes 0..width-1 of
// one machine register (what ldf/st need); a scalar in any one lane. `fixed` pins it to a
// machine register (the ABI's registers at entry, at a trace call and at return).
struct VReg {
  int width = 1;
  int fixed = -1;
  int fixed_lane = 0;  // scalars pinned to one lane
};

// A source operand: element j is component comp[j] of virtual register v, j < n.
struct Src {
  int v = -1;
  std::array<std::uint8_t, 4> comp{0, 1, 2, 3};
  int n = 1;
  bool neg = false;
  bool abs = false;
};

enum class Kind : std::uint8_t {
  kOp,       // mnemonic with dst, srcs and imm
  kLabel,    // target
  kBranch,   // bra target
  kCondBranch,  // bz/bnz srcs[0], target
  kCall,     // call target: clobbers every register; uses and defines fixed vregs
  kRet,      // ret; uses fixed vregs (the payload it returns)
  kHalt,
  kEntry,    // defines the fixed vregs a shader is entered with
  kSpill,    // push the register of srcs[0] (a whole vreg) on the memory stack
  kReload,   // pop the lanes of dst from the memory stack (its kSpill's value)
};

// How a lane-wise instruction's source elements map to swizzle positions: element j of
// every source feeds the lane of the destination's component j (add, mul, mov, ...), or
// sits at swizzle position j (dp3, trace, addresses, branch conditions, push).
enum class Shape : std::uint8_t { kLanewise, kPositional };

struct MInst {
  Kind kind = Kind::kOp;
  std::string mn;
  int dst = -1;
  std::uint8_t dst_comps = 0;  // components of dst written (bit j = component j); 0: all
  bool fresh = false;          // a partial write that starts the vreg: its other lanes are not read
  std::vector<Src> srcs;
  Shape shape = Shape::kLanewise;
  std::string imm;     // immediate, special register, or memory offset text
  bool mem = false;    // srcs[0] is the address (lane x), imm the offset
  bool store = false;  // st: srcs[1] is the stored value (aligned)
  std::string target;  // label
  std::vector<int> defs;  // kCall, kEntry: fixed vregs defined
  std::vector<int> uses;  // kCall, kRet: fixed vregs used
  SourceLocation where;
};

struct MFunction {
  std::string label;     // the code label it starts at
  std::string name;      // for messages: the source file
  std::vector<VReg> vregs;
  std::vector<MInst> code;
  bool is_raygen = false;
};

}  // namespace rpu::cc
