// The back end's machine IR: RPU instructions over virtual registers of 1 to 4 lanes.
// Lowering (lower.cpp) writes it through a Builder (builder.hpp), the register
// allocator (regalloc.cpp) places every virtual register in lanes of a machine register,
// and emit.cpp makes machine instructions of it (machine.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cc/spirv_module.hpp"
#include "isa/instruction.hpp"

namespace rpu::cc {

using isa::Opcode;

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

// A memory-map constant of spec/memory_map.toml by its assembler name (DEVICE_LAUNCH_BASE,
// ...); a name the spec does not have does not compile.
consteval const spec::isa::AsmSymbol& memory_map_symbol(std::string_view name) {
  for (const spec::isa::AsmSymbol& s : spec::isa::kAsmSymbols) {
    if (s.name == name) return s;
  }
  throw "not a memory-map symbol of spec/memory_map.toml";
}

// An immediate operand, typed by what it holds. Which field of the word it fills (imm,
// fimm, sr, a memory offset, a branch target) is the opcode's operand list in
// spec/isa.toml.
struct Imm {
  enum class Type : std::uint8_t {
    kNone,
    kInteger,  // a number: a count, an increment, a byte offset (the listing prints decimal)
    kBits,     // a lane's raw bits: a constant's, a mask (hex)
    kFloat,    // fp32 bits (hex, exact)
    kSpecial,  // a special register's index (its name)
    kSymbol,   // a memory-map constant (its name)
    kLabel,    // a code label: the instruction index it stands for once the code is laid out
  };
  Type type = Type::kNone;
  std::int64_t value = 0;  // all but kLabel: the word holds its low 32 bits
  const spec::isa::AsmSymbol* symbol = nullptr;  // kSymbol
  std::string label;                             // kLabel

  static Imm integer(std::int64_t v) { return of(Type::kInteger, v); }
  static Imm bits(std::uint32_t b) { return of(Type::kBits, b); }
  static Imm fp32_bits(std::uint32_t b) { return of(Type::kFloat, b); }
  static Imm special(std::uint32_t index) { return of(Type::kSpecial, index); }
  // A constant lane's bits: fp32 for lif, raw for li.
  static Imm lane(std::uint32_t b, bool is_float) { return is_float ? fp32_bits(b) : bits(b); }
  static Imm memory_map(const spec::isa::AsmSymbol& s) {
    Imm i = of(Type::kSymbol, s.value);
    i.symbol = &s;
    return i;
  }
  static Imm code_label(std::string name) {
    Imm i = of(Type::kLabel, 0);
    i.label = std::move(name);
    return i;
  }
  std::uint32_t field() const { return static_cast<std::uint32_t>(value); }

 private:
  static Imm of(Type t, std::int64_t v) {
    Imm i;
    i.type = t;
    i.value = v;
    return i;
  }
};

inline Src whole(int v, int width) {
  Src s;
  s.v = v;
  s.n = width;
  return s;
}
inline Src component(const Src& s, int j) {
  Src c = s;
  c.comp[0] = s.comp[static_cast<std::size_t>(j)];
  c.n = 1;
  return c;
}
inline Src neg(Src s) {
  s.neg = !s.neg;
  return s;
}
inline Src abs(Src s) {
  s.abs = true;
  s.neg = false;
  return s;
}
// Every element is element 0 of s.
inline Src broadcast(const Src& s, int n) {
  Src b = s;
  for (int j = 1; j < 4; ++j) b.comp[static_cast<std::size_t>(j)] = s.comp[0];
  b.n = n;
  return b;
}

enum class Kind : std::uint8_t {
  kOp,       // op with dst, srcs and imm
  kLabel,    // label:
  kBranch,   // bra imm
  kCondBranch,  // op (bz/bnz) srcs[0], imm
  kCall,     // call imm: clobbers every register; uses and defines fixed vregs
  kRet,      // ret; uses fixed vregs (the payload it returns)
  kHalt,
  kTrap,     // the all-zero word: the thread stops with an illegal-instruction fault here
  kEntry,    // defines the fixed vregs a shader is entered with
  kSpill,    // push the register of srcs[0] (a whole vreg) on the memory stack
  kReload,   // pop the lanes of dst from the memory stack (its kSpill's value)
};

// srcs are the register operands in the order of the opcode's operands (spec/isa.toml):
// a memory operand's base address (lane x), then a, b, c; a store's data (in lanes x..)
// after its address. How a source's elements map to swizzle positions is the opcode's:
// lane-wise (element j of every source feeds the lane of the destination's component j:
// add, mul, mov, ...), else positional (element j sits at swizzle position j: dp3, trace,
// addresses, branch conditions, push).
struct MInst {
  Kind kind = Kind::kOp;
  Opcode op = Opcode::kMov;    // kOp, kCondBranch
  int dst = -1;
  std::uint8_t dst_comps = 0;  // components of dst written (bit j = component j); 0: all
  bool fresh = false;          // a partial write that starts the vreg: its other lanes are not read
  std::vector<Src> srcs;
  Imm imm;                 // kBranch, kCondBranch, kCall: the target, a label
  std::string label;       // kLabel: the label it defines
  std::string_view note;   // the listing's comment on it
  std::vector<int> defs;  // kCall, kEntry: fixed vregs defined
  std::vector<int> uses;  // kCall, kRet: fixed vregs used
  SourceLocation where;
};

struct MFunction {
  std::string label;     // the code label it starts at
  std::string name;      // for messages: the source file
  std::vector<VReg> vregs;
  std::vector<MInst> code;
};

}  // namespace rpu::cc
