#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cycle/memory_system.hpp"
#include "device/device.hpp"
#include "fp/format.hpp"
#include "isa/firmware.hpp"
#include "memory/memory_image.hpp"
#include "model.hpp"
#include "rpu/harness/chip.hpp"
#include "rpu/spec.hpp"

// One frame on a Verilated chip (docs/chip.md): the firmware into every core's
// code memory, the launch and the scene's traversal configuration, start; the memory
// port served by the cycle model's DRAM (sim/device_dram.hpp) until the chip is done.
// With `lockstep`, a checker per core (sim/spu_checker.hpp) steps the functional model
// and compares every record of the core's trace ports, and the framebuffer must equal
// the functional model's. What the rtl backend (sim/rtl_device.hpp) and chip_cosim
// both run.
namespace rpu::sim {

struct ChipFrame {
  const spec::HardwareConfig* config = nullptr;
  fp::Format format = fp::kFp32;
  std::span<const std::uint8_t> image;
  const ImageLayout* layout = nullptr;
  const isa::Firmware* firmware = nullptr;
  std::span<const std::uint8_t> launch_block;  // with the shader table after it
  device::Launch launch;
  std::uint64_t watchdog = 50'000'000;
};

struct ChipRunOptions {
  bool lockstep = false;
  std::uint64_t max_cycles = 0;  // 0: no limit
  // Pixels whose thread halted, out of all: the frame's progress.
  std::function<void(std::uint64_t done, std::uint64_t total)> progress;
};

// The chip's counters (rpu_top's counters ports), read at the end of a frame.
struct ChipCounters {
  std::vector<streams::CoreCounters> cores;
  std::vector<streams::RayUnitCounters> ray_units;
  // The ray_caches node caches, as many triangle caches, then core c's data cache.
  std::vector<streams::CacheCounters> caches;
  std::size_t ray_caches = 1;
};

// A fault record of the RTL (spec/streams.toml fault).
struct ChipFault {
  std::uint32_t kind = 0, core = 0, thread = 0, pixel = 0, pc = 0, address = 0;
};

struct ChipRunResult {
  std::uint64_t cycles = 0;                 // from start to done and the memory's last write
  std::uint64_t counted_cycles = 0;         // from start to done: what the counters count
  ChipCounters counters;                    // at the end (32 bits each, wrapping)
  std::vector<std::uint8_t> framebuffer;    // pixels x 16 bytes, as the chip wrote them
  std::optional<ChipFault> fault;           // the first faulting pixel's, if any
  std::array<std::uint64_t, spec::isa::kClassCount> retired{};  // thread instructions by class
  std::uint64_t chunk_issues = 0;
  std::uint64_t closest_rays = 0, any_rays = 0;
  cycle::DramStats dram;
  std::uint64_t lockstep_steps = 0;         // with lockstep: functional steps compared
};

// CosimFailure at the first difference (with lockstep), on a model that never ends, or
// on counters that do not add up to the frame's cycles; rpu::Error for a firmware the
// model cannot hold. `info` is what the model was built as (its cores, ray units and
// code words).
ChipRunResult run_chip_frame(Model<harness::Chip>& model, const ModelInfo& info, const ChipFrame& frame,
                             const ChipRunOptions& options);

}  // namespace rpu::sim
