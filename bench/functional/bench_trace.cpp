// Traced rays per second of the golden trace units (fp32 fast path, soft path, packets of
// four rays) and of Embree's rtcIntersect1, on the same scenes and rays in one run
// (docs/perf.md); with packets, the kd nodes they fetch per ray.
//
//   build/release/bench/functional/bench_trace --benchmark_filter=bunny
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <span>
#include <memory>
#include <string>
#include <vector>

#include "embree_scene.hpp"
#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "scene/resolve.hpp"
#include "trace_fixtures.hpp"

namespace rpu::functional {
namespace {

struct Workload {
  Scene scene;
  SceneImage woop, watertight;
  std::unique_ptr<test::EmbreeScene> embree;
  std::vector<TraceRay> primary, random;
};

const Workload& workload(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Workload>> cache;
  auto& w = cache[name];
  if (!w) {
    w = std::make_unique<Workload>();
    w->scene = resolve_scene(name);
    w->woop = make_scene_image(w->scene, KdBuildConfig{}, IsectMode::kWoop);
    w->watertight = make_scene_image(w->scene, KdBuildConfig{}, IsectMode::kWatertight);
    w->embree = std::make_unique<test::EmbreeScene>(w->scene);
    w->primary = test::camera_rays(w->scene, 256, 256);
    w->random = test::random_rays(w->scene, 65536, 1);
  }
  return *w;
}

enum class Engine { kFast32Woop, kFast32Watertight, kSoftWoop, kFast32WoopPackets, kEmbree };

// The rays a chunk of four lanes traces together: four neighbouring pixels of a row
// (primary), four rays in a row of the random set.
constexpr std::size_t kPacketRays = 4;

void trace_rays(benchmark::State& state, const std::string& scene, bool primary, Engine engine) {
  const Workload& w = workload(scene);
  const std::vector<TraceRay>& rays = primary ? w.primary : w.random;
  std::vector<TraceHit> out(rays.size());
  const SceneImage& si = engine == Engine::kFast32Watertight ? w.watertight : w.woop;
  const Tracer tracer(si.image.bytes, si.layout, fp::kFp32, 32, engine != Engine::kSoftWoop);
  std::size_t hits = 0;
  PacketCounters shared;
  for (auto _ : state) {
    if (engine == Engine::kEmbree) {
      for (const TraceRay& r : rays) hits += std::get<0>(w.embree->intersect(r));
    } else if (engine == Engine::kFast32WoopPackets) {
      shared = PacketCounters{};
      for (std::size_t start = 0; start < rays.size(); start += kPacketRays) {
        const std::size_t n = std::min(kPacketRays, rays.size() - start);
        tracer.trace_packets(std::span(rays).subspan(start, n), TraceMode::kClosest, std::span(out).subspan(start, n),
                             kPacketRays, shared);
      }
      hits += out[0].hit;
    } else {
      tracer.trace(rays, TraceMode::kClosest, out);
      hits += out[0].hit;
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rays.size()));
  state.counters["Mrays/s"] =
      benchmark::Counter(static_cast<double>(rays.size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["triangles"] = static_cast<double>(w.scene.triangles.size());
  // The walk's work per ray, from the last pass (every pass traces the same rays), so
  // that a profile's instructions can be put per node visited and per triangle tested.
  if (engine != Engine::kEmbree) {
    double nodes = 0, tests = 0;
    for (const TraceHit& h : out) {
      nodes += h.counters.nodes;
      tests += h.counters.tests;
    }
    state.counters["nodes/ray"] = nodes / static_cast<double>(rays.size());
    state.counters["tests/ray"] = tests / static_cast<double>(rays.size());
  }
  if (engine == Engine::kFast32WoopPackets) {
    state.counters["node fetches/ray"] = static_cast<double>(shared.node_fetches) / static_cast<double>(rays.size());
  }
}

void register_all() {
  for (const std::string scene : {"scenes/bunny.json", "balls:2", "cornell", "scenes/dragon.json"}) {
    for (const bool primary : {true, false}) {
      const std::string rays = primary ? "primary" : "random";
      const std::pair<Engine, const char*> engines[] = {{Engine::kFast32Woop, "rpu_fast32_woop"},
                                                        {Engine::kFast32Watertight, "rpu_fast32_watertight"},
                                                        {Engine::kSoftWoop, "rpu_soft_fp32_woop"},
                                                        {Engine::kFast32WoopPackets, "rpu_fast32_woop_packets4"},
                                                        {Engine::kEmbree, "embree_rtcIntersect1"}};
      for (const auto& [engine, name] : engines) {
        benchmark::RegisterBenchmark((scene + "/" + rays + "/" + name).c_str(),
                                     [=](benchmark::State& s) { trace_rays(s, scene, primary, engine); })
            ->Unit(benchmark::kMillisecond)
            ->MinTime(engine == Engine::kSoftWoop ? 0.5 : 1.0);
      }
    }
  }
}

}  // namespace
}  // namespace rpu::functional

int main(int argc, char** argv) {
  rpu::functional::register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
