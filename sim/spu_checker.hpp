#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fp/format.hpp"
#include "functional/device_memory.hpp"
#include "functional/pixel_map.hpp"
#include "functional/shader_core.hpp"
#include "functional/tracer.hpp"
#include "isa/firmware.hpp"
#include "progen/runner.hpp"
#include "rpu/streams.hpp"

// The lockstep checker of a shader core (ARCHITECTURE.md "Verification", level 2; in
// the manner of Ibex's cosim and OTBN's trace checker): it steps the functional model
// (ShaderCore) in the RTL's order and compares every record of the core's trace ports.
//   issue     the RTL steps chunk c at pc with lanes L: the functional chunk c must be
//             at pc with the lanes L standing there; the checker steps it, and starts
//             the chunk's next round of pixels when the RTL does;
//   retire    each executed lane in its thread's order: pc, instruction word, address;
//   writeback each register write: the lanes of the write mask equal the functional
//             thread's register (which no later step can have changed: the RTL's
//             scoreboard holds back every later writer until this write);
//   fault     kind, thread, pixel, pc and address equal the functional model's fault.
// The first difference throws CosimFailure with a report: cycle, core, thread, pixel,
// pc, the disassembled instruction, and expected against actual per lane.
// One checker follows one core; the functional model has its own memory, so the
// framebuffers can be compared at the end.
namespace rpu::sim {

struct SpuCheckerSetup {
  const isa::Firmware* firmware = nullptr;
  const functional::Tracer* tracer = nullptr;
  fp::Format format = fp::kFp32;
  functional::ShaderCoreConfig core;  // registers, chunk size, depths, watchdog
  std::uint32_t core_id = 0;
  std::uint32_t threads_per_core = 0;
  std::uint32_t cores = 1;            // on the chip (functional::PixelMap: which thread runs which pixel)
  std::uint32_t pixels = 0;
  std::uint32_t width = 1;
  progen::StepObserver* observer = nullptr;  // sees every functional step (coverage)
};

class SpuChecker {
 public:
  // `memory` is the functional model's own (its framebuffer takes the model's stores).
  SpuChecker(const SpuCheckerSetup& setup, functional::DeviceMemory& memory);

  void on_issue(const streams::Issue& r, std::uint64_t cycle);
  void on_retire(const streams::Retire& r, std::uint64_t cycle);
  void on_writeback(const streams::Writeback& r, std::uint64_t cycle);
  void on_fault(const streams::Fault& r, std::uint64_t cycle);
  // The end of the frame: nothing owed, every round the chunks had to run was run.
  // `stop_pixel`: the first faulting pixel of the chip, if any (no round past it starts).
  void finish(std::optional<std::uint32_t> stop_pixel) const;

  std::uint64_t steps() const { return steps_; }
  std::uint64_t retired() const { return retired_; }
  const functional::ShaderStats& stats() const { return stats_; }
  // The first fault in pixel order the functional model met, if any.
  const functional::ShaderFault* first_fault() const;

 private:
  struct Expected {
    std::uint32_t pc = 0;
    std::uint64_t insn = 0;
    std::uint32_t addr = 0;
  };
  struct Chunk {
    functional::ShaderCore::Chunk chunk;
    std::int64_t round = -1;  // none started
    bool started = false;
    std::uint32_t faults_seen = 0;
  };
  struct Thread {
    std::deque<Expected> retires;
    std::map<int, std::deque<std::uint32_t>> writes;  // register -> pcs of the writes owed, oldest first
    std::optional<functional::ShaderFault> fault;
  };

  [[noreturn]] void fail(std::uint64_t cycle, std::uint32_t thread, const std::string& what) const;
  std::string where(std::uint32_t thread) const;
  std::string insn_text(std::uint32_t pc) const;
  void start_round(std::uint32_t c, std::uint64_t cycle);

  SpuCheckerSetup setup_;
  functional::ShaderCore core_;
  std::vector<Chunk> chunks_;
  std::vector<Thread> threads_;
  std::vector<functional::ShaderCore::Lane> lanes_;
  functional::PixelMap map_;
  functional::StepRecord record_;
  functional::ShaderStats stats_;
  std::optional<functional::ShaderFault> first_fault_;
  std::uint64_t steps_ = 0, retired_ = 0;
};

}  // namespace rpu::sim
