// The reference BVH finds the same closest hits as testing every triangle, and a
// finely tessellated sphere is hit where the analytic sphere is.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "reference/bvh.hpp"
#include "scene_builder.hpp"
#include "common/random_vector.hpp"

namespace rpu {
namespace {

Scene random_triangles(int count, std::mt19937& rng) {
  Scene scene;
  const std::uint32_t m = test::add_material(scene, {});
  std::uniform_real_distribution<float> pos(-10.0f, 10.0f), off(-1.0f, 1.0f);
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c{pos(rng), pos(rng), pos(rng)};
    // The last corner first: the order gcc drew them in (common/random_vector.hpp).
    const glm::vec3 corner2 = random_vector<glm::vec3>(off, rng), corner1 = random_vector<glm::vec3>(off, rng),
                    corner0 = random_vector<glm::vec3>(off, rng);
    test::add_triangle(scene, c + corner0, c + corner1, c + corner2, m);
  }
  return scene;
}

// Brute force over all triangles: Moeller-Trumbore written out independently here.
Hit brute_force(const Scene& scene, const Ray& ray) {
  Hit best;
  double t_max = ray.t_max;
  for (std::uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 tri = scene.triangles[i];
    const glm::dvec3 a(scene.positions[tri.x]), b(scene.positions[tri.y]), c(scene.positions[tri.z]);
    const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    const glm::dvec3 s = ray.origin - a, q = glm::cross(s, e1);
    const double u = glm::dot(s, p) / det, v = glm::dot(ray.direction, q) / det, t = glm::dot(e2, q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t <= ray.t_min || t >= t_max) continue;
    best = {t, i, u, v};
    t_max = t;
  }
  return best;
}

TEST(ReferenceBvh, ClosestHitMatchesBruteForceOnRandomTriangles) {
  std::mt19937 rng(7);
  const Scene scene = random_triangles(2000, rng);
  const ReferenceBvh bvh(scene);
  std::uniform_real_distribution<double> u(-15.0, 15.0);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Ray ray{{u(rng), u(rng), u(rng)}, glm::normalize(random_vector(u, rng))};
    const Hit expected = brute_force(scene, ray);
    const Hit got = bvh.closest_hit(ray);
    ASSERT_EQ(got.hit(), expected.hit()) << "ray " << i;
    if (!expected.hit()) continue;
    ++hits;
    // Two triangles can be hit at the very same t; then either id is right.
    EXPECT_NEAR(got.t, expected.t, 1e-9 * expected.t) << "ray " << i;
    EXPECT_EQ(bvh.any_hit(ray), true);
  }
  EXPECT_GT(hits, 3000);  // the test must exercise hits, not only misses
}

TEST(ReferenceBvh, AxisParallelRaysWithZeroComponentsAndOriginsOnBoxPlanes) {
  Scene scene;
  const std::uint32_t m = test::add_material(scene, {});
  test::add_square_z(scene, 4.0f, 0.0f, m);
  test::add_triangle(scene, {-3.0f, -3.0f, 5.0f}, {-2.0f, -3.0f, 5.0f}, {-2.0f, -2.0f, 5.0f}, m);
  const ReferenceBvh bvh(scene);
  // The root box spans z in [0, 5]: origins on its top plane, straight down with +0 and
  // -0 lateral components (reciprocals +-inf in a naive slab test).
  for (double zero : {0.0, -0.0}) {
    for (glm::dvec3 origin : {glm::dvec3(1.0, 0.5, 5.0), glm::dvec3(-1.0, -1.0, 5.0), glm::dvec3(0.0, 0.0, 5.0)}) {
      const Hit hit = bvh.closest_hit({origin, {zero, zero, -1.0}});
      ASSERT_TRUE(hit.hit()) << origin.x << "," << origin.y << " zero " << std::signbit(zero);
      EXPECT_DOUBLE_EQ(hit.t, 5.0);
    }
  }
  EXPECT_FALSE(bvh.closest_hit({{5.0, 0.0, 5.0}, {0.0, 0.0, -1.0}}).hit());
  EXPECT_FALSE(bvh.closest_hit({{0.0, 0.0, 5.0}, {0.0, 0.0, 1.0}}).hit());
}

TEST(ReferenceBvh, EmptySceneNeverHits) {
  const Scene scene;
  const ReferenceBvh bvh(scene);
  EXPECT_FALSE(bvh.closest_hit({{0, 0, 0}, {0, 0, 1}}).hit());
}

// A UV sphere of radius 1 with vertices on the sphere (fp32): the polyhedron lies
// inside the sphere, no deeper than the sagitta 1 - cos(alpha) at a facet, alpha being
// the facet's angular circumradius (<= half the diagonal of a lat-long cell).
TEST(ReferenceBvh, TessellatedSphereHitsWithinSagittaOfAnalyticSphere) {
  constexpr int kLat = 256, kLon = 512;
  Scene scene;
  const std::uint32_t m = test::add_material(scene, {});
  auto at = [](int i, int j) {
    const double theta = std::numbers::pi * i / kLat, phi = 2.0 * std::numbers::pi * j / kLon;
    return glm::vec3(glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
  };
  for (int i = 0; i < kLat; ++i) {
    for (int j = 0; j < kLon; ++j) {
      const glm::vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (i != kLat - 1) test::add_triangle(scene, a, b, c, m);
      if (i != 0) test::add_triangle(scene, a, c, d, m);
    }
  }
  const double dtheta = std::numbers::pi / kLat, dphi = 2.0 * std::numbers::pi / kLon;
  const double alpha = 0.5 * std::hypot(dtheta, dphi);
  const double sagitta = 1.0 - std::cos(alpha);
  // Rays aimed within 0.5 of the centre meet the sphere at <= 30 degrees incidence, so
  // the extra distance along the ray is at most sagitta / cos(30 deg).
  const double tolerance = sagitta / std::cos(std::numbers::pi / 6.0) + 1e-6;
  const ReferenceBvh bvh(scene);
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(-0.5, 0.5), dist(2.0, 50.0);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 dir_out = glm::normalize(random_vector(gauss, rng));
    const glm::dvec3 origin = dir_out * dist(rng);
    glm::dvec3 target = random_vector(unit, rng);
    if (glm::length(target) > 0.5) target *= 0.5 / glm::length(target);
    const glm::dvec3 d = glm::normalize(target - origin);
    // Analytic: |o + t d| = 1, nearer root.
    const double b = glm::dot(origin, d), c = glm::dot(origin, origin) - 1.0;
    const double t_sphere = -b - std::sqrt(b * b - c);
    const Hit hit = bvh.closest_hit({origin, d});
    ASSERT_TRUE(hit.hit()) << "ray " << i;
    EXPECT_GE(hit.t, t_sphere - 1e-6) << "ray " << i << ": hit outside the sphere";
    EXPECT_LE(hit.t, t_sphere + tolerance) << "ray " << i;
    worst = std::max(worst, hit.t - t_sphere);
  }
  RecordProperty("worst_distance_error", std::to_string(worst));
  RecordProperty("tolerance", std::to_string(tolerance));
}

}  // namespace
}  // namespace rpu
