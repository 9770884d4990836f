// Embree (Debian's libembree 3) as an independent hit oracle for the fp32 trace units:
// the closest-hit primitive must agree on >= 99.99% of camera and random rays, t within
// 1e-5 relative where they agree, and every disagreement must be a near tie, checked in
// double precision and reported.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"
#include "embree_scene.hpp"
#include "trace_fixtures.hpp"

namespace rpu::functional {
namespace {

// Exact-as-double ray/triangle distance and the smallest barycentric coordinate (how far
// inside the triangle the ray passes: < 0 outside, ~0 on an edge).
struct DoubleHit {
  double t, min_barycentric;
};
DoubleHit double_hit(const Scene& s, unsigned prim, const TraceRay& r) {
  const glm::dvec3 a(s.positions[s.triangles[prim].x]), b(s.positions[s.triangles[prim].y]),
      c(s.positions[s.triangles[prim].z]);
  const glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.direction[0], r.direction[1], r.direction[2]);
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2), q = glm::cross(o - a, e1);
  const double det = glm::dot(e1, p);
  const double u = glm::dot(o - a, p) / det, v = glm::dot(d, q) / det;
  return {glm::dot(e2, q) / det, std::min({u, v, 1.0 - u - v})};
}

struct OracleCase {
  std::string scene;
  IsectMode mode;
};

class EmbreeOracle : public ::testing::TestWithParam<OracleCase> {};

TEST_P(EmbreeOracle, Fp32ClosestHitsAgreeWithEmbree) {
  const Scene scene = resolve_scene(GetParam().scene);
  const SceneImage si = make_scene_image(scene, KdBuildConfig{}, GetParam().mode);
  const Tracer tracer(si.image.bytes, si.layout, fp::kFp32, 32);
  const test::EmbreeScene embree(scene);
  std::vector<TraceRay> rays = test::camera_rays(scene, 320, 320);  // 102,400 camera rays
  const std::vector<TraceRay> random = test::random_rays(scene, 100000, 41);
  rays.insert(rays.end(), random.begin(), random.end());

  std::size_t agree = 0, hits = 0, near_ties = 0, t_off = 0;
  std::vector<std::string> report;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const TraceHit ours = tracer.trace(rays[i], TraceMode::kClosest);
    const auto [e_hit, e_t, e_prim] = embree.intersect(rays[i]);
    hits += e_hit;
    if (ours.hit == e_hit && (!e_hit || ours.prim == e_prim)) {
      ++agree;
      if (e_hit && std::abs(ours.t - e_t) > 1e-5f * e_t) {
        ++t_off;
        report.push_back(fmt::format("ray {}: prim {} t {} vs Embree {}", i, e_prim, ours.t, e_t));
      }
      continue;
    }
    // A near tie: both answers name triangles the ray meets (within 1e-5 of an edge, in
    // double) at distances equal within 1e-5 relative; or one side misses a triangle the
    // ray only grazes along an edge.
    const double tol = 1e-5;
    bool tie;
    std::string what;
    if (ours.hit && e_hit) {
      const DoubleHit a = double_hit(scene, ours.prim, rays[i]), b = double_hit(scene, e_prim, rays[i]);
      tie = a.min_barycentric > -tol && b.min_barycentric > -tol && std::abs(a.t - b.t) <= tol * std::abs(b.t);
      what = fmt::format("prim {} (t {:.9g}, min bary {:.2g}) vs Embree {} (t {:.9g}, min bary {:.2g})",
                         ours.prim, a.t, a.min_barycentric, e_prim, b.t, b.min_barycentric);
    } else {
      const unsigned prim = ours.hit ? ours.prim : e_prim;
      const DoubleHit h = double_hit(scene, prim, rays[i]);
      tie = std::abs(h.min_barycentric) <= tol;
      what = fmt::format("{} hits prim {} alone (min bary {:.2g})", ours.hit ? "rpu" : "Embree", prim,
                         h.min_barycentric);
    }
    near_ties += tie;
    report.push_back(fmt::format("ray {}: {}: {}", i, tie ? "near tie" : "NOT A TIE", what));
    if (!tie) ADD_FAILURE() << report.back();
  }
  const double agreement = static_cast<double>(agree) / static_cast<double>(rays.size());
  const std::size_t disagreements = rays.size() - agree;
  std::printf("%s %s: %zu rays, %zu hit (Embree), agreement %.5f%%, %zu disagreements (%zu near ties), %zu t off\n",
              GetParam().scene.c_str(), GetParam().mode == IsectMode::kWoop ? "woop" : "watertight", rays.size(),
              hits, 100.0 * agreement, disagreements, near_ties, t_off);
  for (std::size_t i = 0; i < std::min<std::size_t>(report.size(), 20); ++i) std::printf("  %s\n", report[i].c_str());
  RecordProperty("agreement_percent", fmt::format("{:.5f}", 100.0 * agreement));
  EXPECT_GE(agreement, 0.9999);
  EXPECT_EQ(t_off, 0u);
  EXPECT_GT(hits, rays.size() / 4) << "the rays must mostly hit the scene";
}

std::string oracle_name(const ::testing::TestParamInfo<OracleCase>& info) {
  std::string name = info.param.scene;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name + (info.param.mode == IsectMode::kWoop ? "_woop" : "_watertight");
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, EmbreeOracle,
    ::testing::Values(OracleCase{"scenes/bunny.json", IsectMode::kWoop},
                      OracleCase{"scenes/bunny.json", IsectMode::kWatertight},
                      OracleCase{"balls:2", IsectMode::kWoop}, OracleCase{"balls:2", IsectMode::kWatertight},
                      OracleCase{"cornell", IsectMode::kWoop}, OracleCase{"cornell", IsectMode::kWatertight},
                      OracleCase{"scenes/dragon.json", IsectMode::kWoop},
                      OracleCase{"scenes/dragon.json", IsectMode::kWatertight}),
    oracle_name);

}  // namespace
}  // namespace rpu::functional
