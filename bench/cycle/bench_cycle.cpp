// Simulation speed of the cycle backend (docs/perf.md "Cycle model"): host seconds per
// frame next to the functional backend on one host thread, simulated cycles per host
// second, and how host cost follows the work rather than the size of the chip or the
// number of cycles.
//
//   build/release/bench/cycle/bench_cycle
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "asm/assembler.hpp"
#include "asm/builtin_firmware.hpp"
#include "common/hardware_config.hpp"
#include "cycle/cycle_device.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "scene_workload.hpp"

namespace rpu {
namespace {

RenderSettings frame(int size) {
  RenderSettings s;
  s.width = size;
  s.height = size;
  s.spp = 1;
  return s;
}

// Runs `dev` on the frame and reports host time per frame, simulated cycles and
// simulated cycles per host second.
void run(benchmark::State& state, device::Device& dev, const std::string& scene, const isa::Firmware& firmware,
         int size) {
  const bench::SceneWorkload& w = bench::scene_workload(scene);
  double cycles = 0, host = 0;
  for (auto _ : state) {
    device::render_frame(dev, w.scene, w.image.image, firmware, frame(size));
    const device::DeviceStats st = dev.stats();
    host += st.host_seconds;
    if (st.report.find("cycles")) cycles += st.report.number("cycles");
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["host_s/frame"] = host / n;
  if (cycles > 0) {
    state.counters["cycles/frame"] = cycles / n;
    state.counters["sim_cycles/s"] = cycles / host;
  }
}

spec::HardwareConfig sixteen_cores() {
  spec::HardwareConfig c = hardware_config("default");
  c.name = "default x4";
  c.shader_cores = 16;
  c.traversal_units = 16;
  c.intersection_units = 16;
  return c;
}

// The same frame on the functional backend (one host thread) and the cycle backend.
void functional_frame(benchmark::State& state, const std::string& scene) {
  device::FunctionalOptions options;
  options.host_threads = 1;
  const auto dev = device::make_functional_device(hardware_config("default"), fp::kFp32, options);
  run(state, *dev, scene, isa::builtin_firmware("whitted.s"), 128);
}

void cycle_frame(benchmark::State& state, const std::string& scene, const std::string& config) {
  const auto dev = cycle::make_cycle_device(config == "16 cores" ? sixteen_cores() : hardware_config(config), fp::kFp32);
  run(state, *dev, scene, isa::builtin_firmware("whitted.s"), static_cast<int>(state.range(0)));
}

// Host cost per simulated cycle on a frame that mostly waits for DRAM (a long latency,
// a narrow bus) against one that keeps the shader cores issuing (arithmetic only).
const char* kArithmetic = R"(
raygen:
        li      r1, 400
        lif     r2, 1.5
loop:   mad     r3, r2, r2, r3
        mul     r4, r3, r2
        add     r5, r4, r3
        iaddi   r1.x, r1.x, -1
        bnz     r1.x, loop
        halt
hit_whitted:
        ret
)";

void dram_bound(benchmark::State& state) {
  spec::HardwareConfig c = hardware_config("default");
  c.dram.latency = 2000;
  c.dram.bytes_per_cycle = 1;
  const auto dev = cycle::make_cycle_device(c, fp::kFp32);
  run(state, *dev, "cornell", isa::builtin_firmware("whitted.s"), 32);
}

void compute_bound(benchmark::State& state) {
  const auto dev = cycle::make_cycle_device(hardware_config("default"), fp::kFp32);
  const isa::Firmware firmware = isa::assemble(
      "arith.s", [](const std::filesystem::path&) { return std::optional<std::string>(kArithmetic); });
  run(state, *dev, "cornell", firmware, 32);
}

}  // namespace
}  // namespace rpu

using rpu::cycle_frame;
using rpu::functional_frame;

BENCHMARK_CAPTURE(functional_frame, cornell, std::string("cornell"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(cycle_frame, cornell_default, std::string("cornell"), std::string("default"))->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(functional_frame, bunny, std::string("scenes/bunny.json"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(cycle_frame, bunny_default, std::string("scenes/bunny.json"), std::string("default"))->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
// A small frame on the smallest chip and on a 16-core one: host time follows the work.
BENCHMARK_CAPTURE(cycle_frame, cornell_small_tiny, std::string("cornell"), std::string("tiny"))->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(cycle_frame, cornell_small_16_cores, std::string("cornell"), std::string("16 cores"))->Arg(32)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rpu::dram_bound)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rpu::compute_bound)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
