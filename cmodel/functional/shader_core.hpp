#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "fp/format.hpp"
#include "functional/device_memory.hpp"
#include "functional/tracer.hpp"
#include "isa/firmware.hpp"
#include "isa/instruction.hpp"
#include "rpu/spec.hpp"

namespace rpu::functional {

// A shader fault: the run stops and the message names the thread, its pixel, the pc,
// the instruction and (for memory faults) the address (docs/shader-core.md "Faults").
// The kind, pc and address are what the RTL's fault stream carries (spec/isa.toml
// [[fault]]): the address of a memory fault, the shader id of calli's, else 0.
class ShaderFault : public Error {
 public:
  ShaderFault(const std::string& message, std::uint32_t pixel, spec::isa::FaultKind kind, std::uint32_t pc,
              std::uint32_t address)
      : Error(message), pixel_(pixel), kind_(kind), pc_(pc), address_(address) {}
  std::uint32_t pixel() const { return pixel_; }
  spec::isa::FaultKind kind() const { return kind_; }
  std::uint32_t pc() const { return pc_; }
  std::uint32_t address() const { return address_; }

 private:
  std::uint32_t pixel_;
  spec::isa::FaultKind kind_;
  std::uint32_t pc_, address_;
};

// What the shader cores did: instructions retired by class (per thread), issue slots
// of the lockstep chunks, rays and the trace units' counters.
struct ShaderStats {
  std::array<std::uint64_t, spec::isa::kClassCount> retired{};  // thread instructions by class
  std::uint64_t chunk_issues = 0;    // chunk-instructions issued (one per lockstep step)
  std::uint64_t lanes_issued = 0;    // chunk_issues x chunk size: issue slots offered
  std::uint64_t pixels = 0;
  std::uint64_t closest_rays = 0;    // trace
  std::uint64_t any_rays = 0;        // tracea
  std::uint64_t nodes = 0, leaves = 0, tests = 0;  // traversal and intersection work
  // Rays that met the triangle they leave (self_hit in shader_core.cpp; docs/accuracy.md
  // "Self-hits"): the offset of secondary rays failing in the number format.
  std::uint64_t self_hits = 0;
  bool self_hits_counted = false;  // by the functional core's trace; the RTL's units do not know

  std::uint64_t instructions() const;
  ShaderStats& operator+=(const ShaderStats& o);
};

struct ShaderCoreConfig {
  int registers = 32;
  int chunk_size = 4;
  int call_depth = 16;
  std::uint32_t stack_bytes = 16384;
  std::uint64_t watchdog = 50'000'000;  // instructions one thread may retire for one pixel

  // The core of hardware configuration `config`.
  static ShaderCoreConfig of(const spec::HardwareConfig& config, std::uint64_t watchdog);
};

// The bytes the memory stacks of `threads` threads take: each `stack_bytes` and a line
// between (spec/memory_map.toml [device] stack_skew).
inline std::uint32_t stack_region_bytes(std::uint32_t threads, std::uint32_t stack_bytes) {
  return threads * (stack_bytes + spec::memory::kDeviceStackSkew);
}

// The functional shader core: threads grouped into chunks of chunk_size that step in
// lockstep. Every step issues the instruction at the smallest pc among the chunk's
// live threads for the threads standing there (the others are masked off): divergent
// threads reconverge where their paths meet again. Threads share nothing but
// read-only memory, and a thread writes only its own pixel, so the image does not
// depend on the chunk size or on which thread runs which pixel.
// What one lockstep step of a chunk did: the cycle model runs the functional core
// step by step and times these (docs/cycle-model.md); the results stay the core's.
struct MemoryAccess {
  std::uint32_t address = 0;  // byte address
  std::uint32_t bytes = 0;    // 4 or 16
  bool store = false;
  std::uint32_t lane = 0;     // the chunk lane that made it
};

struct StepRecord {
  std::uint32_t pc = 0;
  const isa::Instruction* insn = nullptr;
  std::uint32_t lanes = 0;  // bit l: lane l executed the instruction
  // Memory instructions (loads, stores, push, pop, calli's table read): each executing
  // lane's access, in lane order.
  std::vector<MemoryAccess> accesses;
  // trace/tracea: the walk of each executing lane's ray, in lane order; the first
  // `trace_count` entries are this step's (the vector's storage is reused).
  std::vector<TraceLog> traces;
  std::size_t trace_count = 0;
};

// The pc of the firmware's `raygen` code label, where every thread starts; rpu::Error
// if it has none.
std::uint32_t raygen_entry(const isa::Firmware& firmware);

class ShaderCore {
 public:
  // `firmware`, `memory` and `tracer` must outlive the core. The firmware must have a
  // `raygen` code label (raygen_entry).
  ShaderCore(const isa::Firmware& firmware, DeviceMemory& memory, const Tracer& tracer, fp::Format format,
             const ShaderCoreConfig& config, bool fast_path = true);

  // One thread slot of a chunk: which device thread runs which pixel.
  struct Lane {
    std::uint32_t thread = 0;  // global thread id: names the stack region
    std::uint32_t core = 0, chunk = 0, lane = 0;
    std::uint32_t pixel = 0;   // y * width + x
  };

  struct Thread {
    Lane lane;
    std::uint32_t pc = 0;
    bool done = false;
    std::uint64_t retired = 0;
    std::uint32_t spin = 0;  // instructions retired in a row that wrote nothing but the pc
    std::vector<std::array<std::uint32_t, 4>> regs;
    std::vector<std::uint32_t> returns;                // the return-address stack
    std::vector<std::array<std::uint32_t, 4>> stack;   // push/pop memory stack (its contents)
    std::uint32_t last_hit = 0xffffffffu;  // the triangle of its latest closest hit: the surface its next rays leave
  };

  // A chunk's threads between steps.
  class Chunk {
   public:
    bool done() const { return next_pc_ == kDone; }
    // The fault of the chunk's first faulting pixel so far, or null.
    const ShaderFault* fault() const { return fault_ ? &*fault_ : nullptr; }
    // The pc the next step issues (the smallest live pc); only while !done().
    std::uint32_t next_pc() const { return next_pc_; }
    const std::vector<Thread>& threads() const { return threads_; }

   private:
    friend class ShaderCore;
    static constexpr std::uint32_t kDone = 0xffffffffu;
    void update_next_pc();
    std::vector<Thread> threads_;
    std::uint32_t next_pc_ = kDone;
    std::optional<ShaderFault> fault_;
  };

  // Puts the lanes at raygen with cleared registers.
  void start(Chunk& chunk, std::span<const Lane> lanes, ShaderStats& stats) const;
  // One lockstep step: the instruction at next_pc() for the lanes standing there.
  // A lane that faults stops, and so do the lanes of later pixels, while those of
  // earlier pixels run on: once the chunk is done, fault() is its first faulting pixel's
  // fault in pixel order, whatever the lanes' timing (docs/shader-core.md "Faults").
  // With `record`, reports what the step did. On the fp32 fast path it sets
  // flush-to-zero for the step unless the calling thread holds a FlushScope.
  void step(Chunk& chunk, ShaderStats& stats, StepRecord* record = nullptr);
  // The decoded instruction at `pc`, or null (illegal or past the end).
  const isa::Instruction* instruction(std::uint32_t pc) const {
    return pc < code_.size() && code_[pc].spec ? &code_[pc] : nullptr;
  }
  const isa::RegisterUse& register_use(std::uint32_t pc) const { return uses_[pc]; }
  // The firmware's word at `pc` as the core fetches it, legal or not; 0 past the end.
  std::uint64_t word(std::uint32_t pc) const { return pc < firmware_.code.size() ? firmware_.code[pc] : 0; }

  // Runs the chunk's lanes from raygen until every one halts or faults; then throws the
  // chunk's fault (ShaderFault), if any.
  // With `end_registers`, receives each lane's registers after its halt (for tests
  // that check a program's end state); with `observe`, is called after every step.
  using StepObserver = std::function<void(const StepRecord&, const Chunk&)>;
  void run_chunk(std::span<const Lane> lanes, ShaderStats& stats,
                 std::vector<std::vector<std::array<std::uint32_t, 4>>>* end_registers = nullptr,
                 const StepObserver* observe = nullptr);
  // One line of a pixel's trace (rpu render --pixel): the pc, its source line, the
  // instruction, and what it wrote to a register after `record`'s step, for the thread
  // `after`: each lane as a float (as an integer where the exponent bits are 0), then
  // the bits.
  std::string trace_line(const StepRecord& record, const Thread& after) const;

 private:
  template <class Arith>
  void step_with(const Arith& ar, Chunk& chunk, ShaderStats& stats, StepRecord* record);
  template <class Arith>
  void execute(const Arith& ar, Thread& t, ShaderStats& stats, StepRecord* record);
  [[noreturn]] void fault(const Thread& t, spec::isa::FaultKind kind, const std::string& what,
                          std::uint32_t address = 0) const;
  // The address of stack slot `slot` (0 the first pushed) of device thread `thread`:
  // the stacks grow down from the top of their thread's region (docs/shader-core.md "Memory").
  std::uint32_t stack_slot(std::uint32_t thread, std::uint32_t slot) const;

  const isa::Firmware& firmware_;
  DeviceMemory& memory_;
  const Tracer& tracer_;
  fp::Format format_;
  ShaderCoreConfig config_;
  bool fast_;
  std::uint32_t raygen_ = 0;
  std::vector<isa::Instruction> code_;    // decoded; spec == nullptr where illegal
  std::vector<isa::RegisterUse> uses_;    // per pc, of the decoded instructions
  std::vector<std::string> illegal_why_;  // per pc, why it did not decode
};

}  // namespace rpu::functional
