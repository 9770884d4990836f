// A ray's distance to a split plane, as a BSP walk computes it at each node: to an
// axis-aligned plane (axis, position: t = (split - o[axis]) / d[axis], the reciprocal of
// the direction precomputed per ray, as every kd-tree walk does) and to an arbitrary
// plane (normal, offset: t = (offset - n.o) / n.d, both dot products depending on the
// ray). Two ways: `chain`, the next plane depending on the side this test finds, as the
// walk's next node does (one dependent chain, never vectorised); `stream`, every plane in
// turn, independent tests the compiler may vectorise (a packet or beam walk's case).
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

namespace {

constexpr std::uint32_t kPlanes = 4096;  // a power of two: the next index is masked
constexpr int kTestsPerIteration = 1 << 16;

struct AxisPlane {
  int axis;
  double split;
};

struct Plane {
  glm::dvec3 normal;
  double offset;
};

struct Workload {
  std::vector<AxisPlane> axis_planes;
  std::vector<Plane> planes;
  glm::dvec3 origin, direction, inverse;

  Workload() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (std::uint32_t i = 0; i < kPlanes; ++i) {
      axis_planes.push_back({static_cast<int>(rng() % 3), unit(rng)});
      planes.push_back({glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng))), unit(rng)});
    }
    origin = {0.1, -0.2, 0.3};
    direction = glm::normalize(glm::dvec3(0.3, 0.5, -0.8));
    inverse = 1.0 / direction;
  }
};

const Workload& workload() {
  static const Workload w;
  return w;
}

// Runs `test(plane)` kTestsPerIteration times, chained or streamed (state.range(0)).
template <typename Planes, typename Test>
void run(benchmark::State& state, const Planes& planes, Test test) {
  const bool chain = state.range(0) == 0;
  for (auto _ : state) {
    std::uint32_t node = 0;
    double sum = 0.0;
    for (int k = 0; k < kTestsPerIteration; ++k) {
      const double t = test(planes[chain ? node : static_cast<std::uint32_t>(k) & (kPlanes - 1)]);
      if (chain) node = (2 * node + 1 + (t > 0.0 ? 1u : 0u)) & (kPlanes - 1);
      sum += t;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kTestsPerIteration);
  state.SetLabel(chain ? "chain" : "stream");
}

void axis_aligned_plane(benchmark::State& state) {
  const Workload& w = workload();
  run(state, w.axis_planes, [&](const AxisPlane& p) { return (p.split - w.origin[p.axis]) * w.inverse[p.axis]; });
}

void arbitrary_plane(benchmark::State& state) {
  const Workload& w = workload();
  run(state, w.planes, [&](const Plane& p) {
    return (p.offset - glm::dot(p.normal, w.origin)) / glm::dot(p.normal, w.direction);
  });
}

}  // namespace

BENCHMARK(axis_aligned_plane)->ArgName("stream")->Arg(0)->Arg(1);
BENCHMARK(arbitrary_plane)->ArgName("stream")->Arg(0)->Arg(1);
BENCHMARK_MAIN();
