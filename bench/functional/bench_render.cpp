// Functional rendering throughput: the Whitted firmware on the functional device
// (shader cores + trace units), rays per second with shading, on 1 and 2 host threads
// (docs/perf.md).
//
//   build/release/bench/functional/bench_render
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "asm/builtin_firmware.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "scene_workload.hpp"

namespace rpu {
namespace {

void render(benchmark::State& state, const std::string& scene, bool soft_path) {
  const bench::SceneWorkload& w = bench::scene_workload(scene);
  const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
  RenderSettings settings;
  settings.width = 128;
  settings.height = 128;
  settings.spp = 1;
  device::FunctionalOptions options;
  options.host_threads = static_cast<int>(state.range(0));
  options.fast_path = !soft_path;
  const auto dev = device::make_functional_device(hardware_config("default"), fp::kFp32, options);
  std::uint64_t rays = 0, instructions = 0;
  for (auto _ : state) {
    device::render_frame(*dev, w.scene, w.image.image, firmware, settings);
    const functional::ShaderStats& s = dev->stats().shader;
    rays += s.closest_rays + s.any_rays;
    instructions += s.instructions();
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["instr/s"] = benchmark::Counter(static_cast<double>(instructions), benchmark::Counter::kIsRate);
}

}  // namespace
}  // namespace rpu

using rpu::render;

// Real time: the work is spread over host threads.
BENCHMARK_CAPTURE(render, cornell_fast32, std::string("cornell"), false)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(render, bunny_fast32, std::string("scenes/bunny.json"), false)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(render, balls_fast32, std::string("balls:2"), false)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(render, cornell_soft, std::string("cornell"), true)->Arg(1)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
