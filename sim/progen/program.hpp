#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "isa/firmware.hpp"
#include "isa/instruction.hpp"
#include "progen/fault_class.hpp"

// A random shader program as the generator makes it: structured statements (straight
// code, if/else, counted loops, calls, push/pop regions) that render to assembly text
// (docs/assembler.md). The structure is what makes every program legal and terminating
// by construction, and what the shrinker edits (docs/random-programs.md).
namespace rpu::progen {

// The machine a program is made for: the fields of spec::HardwareConfig it depends on.
struct Machine {
  int registers = 32;
  int chunk_size = 4;
  int call_depth = 16;
  std::uint32_t stack_bytes = 16384;
};

// Three registers at the top of the file hold what every statement may rely on; no
// generated instruction writes them (the loop counter is saved and restored by each
// loop), so a statement is legal wherever it stands. r0 .. r(registers - 4) are free.
struct RegisterPlan {
  std::uint8_t pixel = 0;    // rdsr pixel: (x, y, y * width + x, 0)
  std::uint8_t bases = 0;    // addresses: (own framebuffer pixel, launch block, .data, image)
  std::uint8_t counter = 0;  // lane x: the innermost loop's remaining trips
  int free = 0;              // r0 .. r(free - 1) are free

  static RegisterPlan for_registers(int registers);
};

// Lanes of RegisterPlan::bases.
inline constexpr int kBaseFramebuffer = 0, kBaseLaunch = 1, kBaseData = 2, kBaseImage = 3;

// A lane-dependent condition: `setup` computes a value; the then-part runs in the lanes
// where lane `lane` of `reg` is nonzero (or zero, with `when_zero`).
struct Condition {
  std::vector<isa::Instruction> setup;
  std::uint8_t reg = 0;
  std::uint8_t swizzle = 0;  // of the branch's source; its lane x names the lane tested
  bool when_zero = false;
  // The smallest pixel index for which the then-part runs, where the generator knows
  // it (conditions on the pixel index only); the first faulting pixel of a fault
  // program follows from it.
  std::optional<std::uint32_t> first_pixel;
  std::string text;  // what it tests, for the comment
};

enum class StatementKind : unsigned char {
  kInstruction,    // one instruction that is legal in any register state
  kGroup,          // statements under one comment (a camera ray, an inlined call)
  kIndexedLoad,    // an address computed into a free register, then a load from it
  kIf,             // condition; body where it holds, other where it does not
  kLoop,           // `insns` set the counter to 1 .. trips; body runs that many times
  kCall,           // call routines[routine]
  kCalli,          // `insns` compute a shader id in shader_lo .. shader_hi, then calli
  kPushPop,        // insns = pushes then as many pops; body between them
  kReturnAddress,  // insns = mfra, mtra: the return address through a register
  kHalt,
  kFault,          // `fault`: code that faults (only at the top level of raygen)
};

// What a fault statement runs: `before`, then `repeated` `repeat` times (a counted loop),
// then `after`, then (for the pc fault) a branch past the end of the code, or (for the
// spin fault) a loop that writes nothing: `spin` conditional branches back to its top,
// then a bra to it. Words, not instructions, because some are illegal; they print as
// disassembly or `.insn`.
struct FaultCode {
  FaultClass fault = FaultClass::kNone;
  std::vector<std::uint64_t> before;
  std::uint32_t repeat = 0;
  std::vector<std::uint64_t> repeated;
  std::vector<std::uint64_t> after;
  bool branch_past_end = false;
  bool spin = false;
  std::vector<isa::Instruction> spin_branches;
  std::string text;  // what it does, for the comment
};

struct Statement {
  StatementKind kind = StatementKind::kInstruction;
  std::vector<isa::Instruction> insns;
  std::string note;  // the comment it prints with
  Condition condition;
  std::uint32_t trips = 0;  // kLoop: at most this many
  int routine = -1;         // kCall
  int shader_lo = 0, shader_hi = 0;  // kCalli
  std::vector<Statement> body, other;
  FaultCode fault;
};

// A function (reached by call) or a hit shader (reached by calli through the shader
// table, label hit_<name>). Routine i calls only routines j > i, so calls nest at most
// as deep as there are routines and never recurse.
struct Routine {
  std::string label;  // "f3" or "hit_s1"
  bool shader = false;
  // Entered with mfra + push and left with pop + mtra, as whitted.s's recursive
  // routines keep their return address (docs/shader-core.md "The shader ABI").
  bool keeps_return_address = false;
  std::uint8_t return_register = 0;  // which register carries it
  std::uint8_t return_lane = 0;
  std::vector<Statement> body;
};

// What running a statement can cost a thread, at most: instructions retired, memory
// stack entries (16 bytes each) and return-stack entries it adds at its peak.
struct Cost {
  std::uint64_t instructions = 0;
  std::uint32_t stack = 0;
  std::uint32_t returns = 0;
};

struct Program {
  std::uint64_t seed = 0;
  Machine machine;
  RegisterPlan regs;
  FaultClass fault = FaultClass::kNone;  // what every run must end in
  std::uint64_t watchdog_limit = 0;      // a watchdog-fault program's limit
  std::vector<std::uint32_t> data;       // the .data words
  std::vector<Statement> raygen;         // after the prologue, before the halt
  std::vector<Routine> routines;

  // The assembly source: readable, with comments naming each statement kind.
  std::string assembly() const;
  // assembly() through rpu_asm; rpu::Error with the assembler's message if it fails
  // (a generator bug).
  isa::Firmware firmware() const;
  // The names whose hit_<name> labels the launch binds into the shader table, in
  // shader-id order.
  std::vector<std::string> shader_names() const;

  // The most any thread can cost (raygen, every loop at its most trips, every call).
  Cost cost() const;
  // The watchdog a run must use: the limit for a watchdog-fault program, else the
  // instruction bound, which no thread can exceed (docs/random-programs.md).
  std::uint64_t watchdog() const;
  // The pixel whose fault a run reports (the first faulting pixel): nullopt for a
  // program that halts, or when a statement hides it.
  std::optional<std::uint32_t> fault_pixel() const;
  // Statements in raygen and every routine, nested ones included.
  std::size_t statement_count() const;
};

// The costs of a program's statements. Routine i calls only routines after it, so the
// costs are computed from the last routine to the first; the generator, which makes
// routines in that order, updates each as it is made.
class CostModel {
 public:
  explicit CostModel(const Program& program);

  Cost statement(const Statement& statement) const;
  Cost sequence(const std::vector<Statement>& statements) const;
  Cost routine(int index) const { return routines_[static_cast<std::size_t>(index)]; }
  // Recomputes routine `index` of `program` from its body (routines after it current).
  void update(const Program& program, int index);

 private:
  std::vector<Cost> routines_;           // by routine index
  std::vector<int> shader_routine_;      // routine index by shader id
};

// The cost of the code a fault statement runs, in a faulting lane.
std::uint64_t fault_instructions(const FaultCode& code);

// An instruction whose only effect is to compute its destination from registers and
// immediates, so that any operands make a legal instruction of it.
bool is_pure_compute(const spec::isa::InsnSpec& spec);

}  // namespace rpu::progen
