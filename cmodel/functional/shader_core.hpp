#pragma once

#include <array>
#include <cstdint>
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
class ShaderFault : public Error {
 public:
  ShaderFault(const std::string& message, std::uint32_t pixel) : Error(message), pixel_(pixel) {}
  std::uint32_t pixel() const { return pixel_; }

 private:
  std::uint32_t pixel_;
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

  std::uint64_t instructions() const;
  ShaderStats& operator+=(const ShaderStats& o);
};

struct ShaderCoreConfig {
  int registers = 32;
  int chunk_size = 4;
  int call_depth = 16;
  std::uint32_t stack_bytes = 4096;
  std::uint64_t watchdog = 50'000'000;  // instructions one thread may retire for one pixel
};

// The functional shader core: threads grouped into chunks of chunk_size that step in
// lockstep. Every step issues the instruction at the smallest pc among the chunk's
// live threads for the threads standing there (the others are masked off): divergent
// threads reconverge where their paths meet again. Threads share nothing but
// read-only memory, and a thread writes only its own pixel, so the image does not
// depend on the chunk size or on which thread runs which pixel.
class ShaderCore {
 public:
  // `firmware`, `memory` and `tracer` must outlive the core. The firmware must have a
  // `raygen` code label.
  ShaderCore(const isa::Firmware& firmware, DeviceMemory& memory, const Tracer& tracer, fp::Format format,
             const ShaderCoreConfig& config, bool fast_path = true);

  // One thread slot of a chunk: which device thread runs which pixel.
  struct Lane {
    std::uint32_t thread = 0;  // global thread id: names the stack region
    std::uint32_t core = 0, chunk = 0, lane = 0;
    std::uint32_t pixel = 0;   // y * width + x
  };

  // Runs the chunk's lanes from raygen until every one halts. Throws ShaderFault.
  // With `end_registers`, receives each lane's registers after its halt (for tests
  // that check a program's end state).
  void run_chunk(std::span<const Lane> lanes, ShaderStats& stats,
                 std::vector<std::vector<std::array<std::uint32_t, 4>>>* end_registers = nullptr);

 private:
  struct Thread;
  template <class Ops>
  void run_chunk_with(const Ops& ops, std::span<const Lane> lanes, ShaderStats& stats,
                      std::vector<std::vector<std::array<std::uint32_t, 4>>>* end_registers);
  template <class Ops>
  void execute(const Ops& ops, Thread& t, ShaderStats& stats);
  [[noreturn]] void fault(const Thread& t, const std::string& what) const;

  const isa::Firmware& firmware_;
  DeviceMemory& memory_;
  const Tracer& tracer_;
  fp::Format format_;
  ShaderCoreConfig config_;
  bool fast_;
  std::uint32_t raygen_ = 0;
  std::vector<isa::Instruction> code_;    // decoded; spec == nullptr where illegal
  std::vector<std::string> illegal_why_;  // per pc, why it did not decode
};

}  // namespace rpu::functional
