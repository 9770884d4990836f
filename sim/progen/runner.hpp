#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "device/device.hpp"
#include "fp/format.hpp"
#include "functional/device_memory.hpp"
#include "functional/pixel_map.hpp"
#include "functional/scene_image.hpp"
#include "functional/shader_core.hpp"
#include "progen/program.hpp"
#include "rpu/spec.hpp"

// Random programs on the functional golden model, one lockstep step at a time, as a
// launch on the device runs them (docs/shader-core.md): pixels on threads as
// functional::PixelMap assigns them, chunks in pixel order, the fault of the first
// faulting pixel reported.
// The RTL co-simulation builds its memory and lanes with the same functions, so that
// both sides run the same launch.
namespace rpu::progen {

// Sees every step of a run (coverage, or a shrinking predicate's test).
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual void start_chunk(const functional::ShaderCore::Chunk& chunk) { (void)chunk; }
  // Before the step that issues chunk.next_pc().
  virtual void before_step(const functional::ShaderCore::Chunk& chunk) { (void)chunk; }
  virtual void after_step(const functional::StepRecord& record, const functional::ShaderCore::Chunk& chunk) = 0;
};

struct Outcome {
  std::optional<std::string> fault;  // the reported fault's message; nullopt: every thread halted
  std::optional<std::uint32_t> fault_pixel;
  std::uint64_t steps = 0;              // lockstep issues of all chunks
  std::uint64_t instructions = 0;       // retired by all threads
  std::uint64_t most_instructions = 0;  // retired by the busiest thread
};

struct RunnerOptions {
  std::string scene = "tetra:1";  // as `rpu render` takes it; any scene with a triangle
  // The launch; 0 means chunk_size x 2 pixels: two chunks, so that faults and
  // divergence meet the chunk boundary.
  int width = 0, height = 0;
};

class Runner {
 public:
  // Builds the scene's memory image for the configuration's number format.
  Runner(const spec::HardwareConfig& config, const RunnerOptions& options = {});
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  // Assembles the program and runs its launch. rpu::Error if it does not assemble or
  // lacks a hit_<name> label (generator bugs); faults are outcomes, not errors.
  Outcome run(const Program& program, StepObserver* observer = nullptr) const;

  // The pieces of that launch, for another model of the chip to run it too.
  const spec::HardwareConfig& config() const { return config_; }
  fp::Format format() const { return format_; }
  const device::Launch& launch() const { return launch_; }
  const functional::SceneImage& scene() const { return scene_; }
  const functional::Tracer& tracer() const { return *tracer_; }
  // The shader table binding the program's hit_<name> labels, in shader-id order.
  std::vector<std::uint32_t> shader_table(const Program& program, const isa::Firmware& firmware) const;
  functional::DeviceMemory memory(const Program& program, const isa::Firmware& firmware) const;
  functional::ShaderCoreConfig core_config(const Program& program) const;
  // Blocks of the launch, a chunk's work for a round each, in pixel order (which is
  // the order faults are reported in).
  functional::PixelMap pixel_map() const;

 private:
  spec::HardwareConfig config_;
  fp::Format format_;
  functional::SceneImage scene_;
  device::Launch launch_;
  std::unique_ptr<functional::Tracer> tracer_;
};

// What is wrong with a run of `program`, or "" if it ended as the program says it must:
// halted within its instruction bound, or faulted with its fault class at its first
// faulting pixel.
std::string unexpected(const Program& program, const Outcome& outcome);

}  // namespace rpu::progen
