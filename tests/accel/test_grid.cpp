// The uniform grid's own rules: early termination, mailboxes, the resolution heuristic.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "accel/brute_force.hpp"
#include "accel/ray_sets.hpp"
#include "accel/uniform_grid.hpp"
#include "common/error.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel {
namespace {

Scene two_triangles(const glm::vec3 (&a)[3], const glm::vec3 (&b)[3]) {
  Scene s;
  s.materials.push_back({});
  for (const glm::vec3& v : a) s.positions.push_back(v);
  for (const glm::vec3& v : b) s.positions.push_back(v);
  s.triangles = {{0, 1, 2}, {3, 4, 5}};
  s.material_ids = {0, 0};
  return s;
}

// Triangle 0 leans along the ray: it lies in the ray's first cells, a little below the
// ray, and meets the ray only at x = 9 (t = 10). Triangle 1 stands across the ray at
// x = 5 (t = 6), in cells the walk reaches later. A walk that accepts the first hit it
// finds returns triangle 0.
TEST(UniformGrid, AHitBeyondTheCurrentCellDoesNotEndTheWalk) {
  const Scene s = two_triangles({{0.0f, 0.45f, -5.0f}, {0.0f, 0.45f, 5.0f}, {10.0f, 0.45f + 10.0f / 180.0f, 0.5f}},
                                {{5.0f, 0.2f, 0.2f}, {5.0f, 0.9f, 0.3f}, {5.0f, 0.3f, 0.9f}});
  const TriangleSet triangles(s);
  const UniformGrid grid(triangles, 500.0, true);
  ASSERT_GT(grid.resolution().x, 10);
  const Ray ray{{-1.0, 0.5, 0.5}, {1.0, 0.0, 0.0}};

  // Triangle 0 is met in the cells before x = 3: a ray that ends there tests it.
  RayCost before;
  EXPECT_FALSE(grid.any_hit({ray.origin, ray.direction, 0.0, 4.0}, before));
  EXPECT_EQ(before.tests, 1u);

  RayCost cost;
  const Hit hit = grid.closest_hit(ray, cost);
  EXPECT_EQ(hit.prim, 1u);
  EXPECT_NEAR(hit.t, 6.0, 1e-12);
  EXPECT_EQ(cost.tests, 2u);  // each triangle once: triangle 0 is mailboxed after its first cell
  RayCost brute_cost;
  const Hit expected = BruteForce(triangles).closest_hit(ray, brute_cost);
  EXPECT_EQ(hit.prim, expected.prim);
  EXPECT_EQ(hit.t, expected.t);

  // Without mailboxes the same answer, triangle 0 tested in every cell it shares with the ray.
  const UniformGrid plain(triangles, 500.0, false);
  RayCost plain_cost;
  const Hit plain_hit = plain.closest_hit(ray, plain_cost);
  EXPECT_EQ(plain_hit.prim, 1u);
  EXPECT_EQ(plain_hit.t, hit.t);
  EXPECT_GT(plain_cost.tests, cost.tests);
}

TEST(UniformGrid, MailboxesTestEachTriangleAtMostOncePerRayAndChangeNoAnswer) {
  const Scene s = resolve_scene("cornell");
  const TriangleSet triangles(s);
  const UniformGrid with(triangles, 4.0, true), without(triangles, 4.0, false);
  std::uint64_t tests_with = 0, tests_without = 0;
  for (const Ray& r : random_rays(triangles, 5000, 3)) {
    RayCost a, b;
    const Hit ha = with.closest_hit(r, a), hb = without.closest_hit(r, b);
    ASSERT_EQ(ha.prim, hb.prim);
    ASSERT_EQ(ha.t, hb.t);
    ASSERT_LE(a.tests, triangles.size());
    ASSERT_LE(a.tests, b.tests);
    ASSERT_EQ(with.any_hit(r, a), without.any_hit(r, b));
    tests_with += a.tests;
    tests_without += b.tests;
  }
  EXPECT_LT(tests_with, tests_without);  // Cornell's walls span many cells
}

TEST(UniformGrid, MakesAboutLambdaCellsPerTriangleOfOneShape) {
  const Scene s = resolve_scene("tetra:5");  // 1024 triangles filling a cube
  const TriangleSet triangles(s);
  for (const double lambda : {1.0, 4.0, 16.0}) {
    const UniformGrid grid(triangles, lambda, true);
    const double wanted = lambda * static_cast<double>(triangles.size());
    EXPECT_GT(static_cast<double>(grid.node_count()), 0.7 * wanted) << "lambda " << lambda;
    EXPECT_LT(static_cast<double>(grid.node_count()), 1.4 * wanted) << "lambda " << lambda;
    const glm::ivec3 r = grid.resolution();
    EXPECT_LE(std::abs(r.x - r.y), 1);  // a cube gets cubic cells
    EXPECT_LE(std::abs(r.y - r.z), 1);
  }
}

TEST(UniformGrid, AFlatSceneGetsOneCellAcrossItsFlatAxis) {
  Scene s;
  s.materials.push_back({});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 200; ++i) {
    const float x = u(rng);
    const float y = u(rng);
    s.positions.insert(s.positions.end(), {{x, y, 0.0f}, {x + 0.05f, y, 0.0f}, {x, y + 0.05f, 0.0f}});
    const auto v = static_cast<std::uint32_t>(3 * i);
    s.triangles.emplace_back(v, v + 1, v + 2);
    s.material_ids.push_back(0);
  }
  const TriangleSet triangles(s);
  const UniformGrid grid(triangles, 4.0, true);
  EXPECT_EQ(grid.resolution().z, 1);
  EXPECT_NEAR(static_cast<double>(grid.node_count()), 800.0, 100.0);
  // Rays straight down onto the plane find what brute force finds.
  const BruteForce brute(triangles);
  std::uniform_real_distribution<double> p(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const double x = p(rng);
    const double y = p(rng);
    const Ray r{{x, y, 1.0}, {0.0, 0.0, -1.0}};
    RayCost cost;
    const Hit a = grid.closest_hit(r, cost), b = brute.closest_hit(r, cost);
    ASSERT_EQ(a.prim, b.prim) << "x " << x << " y " << y;
    ASSERT_EQ(a.t, b.t);
  }
}

TEST(UniformGrid, RejectsALambdaThatIsNotAPositiveNumber) {
  const Scene s = resolve_scene("tetra:1");
  const TriangleSet triangles(s);
  for (const double lambda : {0.0, -1.0, std::nan("")}) {
    EXPECT_THROW(UniformGrid(triangles, lambda, true), Error) << lambda;
  }
}

}  // namespace
}  // namespace rpu::accel
