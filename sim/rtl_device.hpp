#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "device/device.hpp"
#include "memory/memory_image.hpp"

// The rtl backend of the Device API (docs/chip.md): the frame runs on the
// Verilated chip (rtl/rpu_top.sv) of a named configuration, its memory port served by
// the cycle model's DRAM; the host side (scene, tree, image, firmware, launch block)
// is the other backends' own code. The RTL keeps its build-time parameters, so only a
// named configuration with a model in this build runs (rpu::Error otherwise, naming
// what was built).
namespace rpu::sim {

struct RtlOptions {
  std::uint64_t watchdog = 50'000'000;  // instructions per thread and pixel (at most 2^32 - 1)
  IsectMode isect = IsectMode::kWoop;
  bool lockstep = false;                // compare every core with the functional model
  std::string waves;                    // FST waveforms of the window below, if given
  std::uint64_t wave_begin = 0, wave_end = ~std::uint64_t{0};
};

std::unique_ptr<device::Device> make_rtl_device(const spec::HardwareConfig& config, fp::Format format,
                                                const RtlOptions& options = {});

// The configurations and intersection tests a chip model was built for, "tiny/woop ...".
std::string rtl_models_built();

// rpu::Error unless this build has a Verilated chip for `config` as spec/configs.toml
// names it, in its own format, with `isect`.
void check_rtl_runs(const spec::HardwareConfig& config, fp::Format format, IsectMode isect);

}  // namespace rpu::sim
