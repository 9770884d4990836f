// SAH kd-tree build time against triangle count (docs/kdtree.md, "Build speed"):
// random triangle soups of 10^3 to 10^6 triangles, fitted to N log N, and the dragon
// meshes from the mesh cache (scripts/fetch-meshes) when they are there.
//
//   build/ci/bench/kdtree/bench_kdtree
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "kdtree/kdtree.hpp"
#include "scene/mesh.hpp"
#include "common/random_vector.hpp"

namespace rpu {
namespace {

// n triangles of random size and orientation in the unit cube, the sizes spread so
// that the soup is neither uniform nor one clump.
Scene random_soup(std::size_t n) {
  Scene s;
  s.source = "random soup";
  std::mt19937_64 rng(n);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float scale = 1.0f / std::cbrt(static_cast<float>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 centre = random_vector<glm::vec3>(u, rng);
    const float size = 2.0f * scale * u(rng);
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (int v = 0; v < 3; ++v) s.positions.push_back(centre + size * (random_vector<glm::vec3>(u, rng) - 0.5f));
    s.triangles.emplace_back(base, base + 1, base + 2);
    s.material_ids.push_back(0);
  }
  return s;
}

void report(benchmark::State& state, const Scene& scene, const KdTree& tree) {
  state.SetComplexityN(static_cast<std::int64_t>(scene.triangles.size()));
  state.counters["tris"] = static_cast<double>(scene.triangles.size());
  state.counters["nodes"] = static_cast<double>(tree.stats.nodes);
  state.counters["refs/tri"] = static_cast<double>(tree.stats.prim_refs) / static_cast<double>(scene.triangles.size());
  state.counters["sah"] = tree.stats.sah_cost;
  state.counters["depth"] = tree.stats.max_depth;
}

void run(benchmark::State& state, const Scene& scene, bool perfect) {
  KdBuildConfig config = kd_build_config_for("default");
  config.perfect_splits = perfect;
  KdTree tree;
  for (auto _ : state) {
    tree = build_kdtree(scene, config);
    benchmark::DoNotOptimize(tree.nodes.data());
  }
  report(state, scene, tree);
}

void soup(benchmark::State& state, bool perfect) {
  const Scene scene = random_soup(static_cast<std::size_t>(state.range(0)));
  run(state, scene, perfect);
}

void soup_bbox(benchmark::State& state) { soup(state, false); }
void soup_perfect(benchmark::State& state) { soup(state, true); }
BENCHMARK(soup_bbox)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);
BENCHMARK(soup_perfect)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);

// The dragons, registered only when the mesh cache holds them.
void register_meshes() {
  for (const char* name : {"dragon_11k", "dragon_48k", "dragon_203k", "dragon_872k"}) {
    const std::filesystem::path path = mesh_cache_dir() / (std::string(name) + ".ply");
    if (!std::filesystem::exists(path)) continue;
    const auto mesh = std::make_shared<const Scene>(load_mesh(path, MeshOptions{}));
    for (const bool perfect : {false, true}) {
      benchmark::RegisterBenchmark((std::string(name) + (perfect ? "_perfect" : "_bbox")).c_str(),
                                   [mesh, perfect](benchmark::State& state) { run(state, *mesh, perfect); })
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace
}  // namespace rpu

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rpu::register_meshes();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
