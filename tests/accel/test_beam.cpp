// Beam tracing: the frustum culls only what no ray of the beam can meet, and every ray
// gets exactly the hit it gets alone.
#include <vector>

#include <gtest/gtest.h>

#include "accel/beam.hpp"
#include "accel/bvh.hpp"
#include "accel/ray_sets.hpp"
#include "common/error.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel {
namespace {

// Four rays from the origin through the corners of [-1, 1]^2 at z = 1 (a beam down +z).
std::vector<Ray> square_beam() {
  return {{{0, 0, 0}, {-1, -1, 1}}, {{0, 0, 0}, {1, -1, 1}}, {{0, 0, 0}, {1, 1, 1}}, {{0, 0, 0}, {-1, 1, 1}}};
}

TEST(Frustum, MissesOnlyBoxesAndTrianglesBeyondAPlane) {
  const std::vector<Ray> rays = square_beam();
  const Frustum f(rays, {0, 1, 2, 3});
  EXPECT_EQ(f.planes(), 4);
  EXPECT_TRUE(f.misses_box({3, -1, 1}, {4, 1, 2}));      // right of the beam at z 1..2 (x <= z there)
  EXPECT_TRUE(f.misses_box({-1, -1, -3}, {1, 1, -2}));   // behind the origin
  EXPECT_FALSE(f.misses_box({-0.1, -0.1, 5}, {0.1, 0.1, 6}));  // on the axis
  EXPECT_FALSE(f.misses_box({1.9, -0.1, 2}, {2.5, 0.1, 3}));   // through the plane x = z
  EXPECT_FALSE(f.misses_box({-1, -1, -1}, {1, 1, 1}));         // around the origin
  EXPECT_TRUE(f.misses_triangle({{3, 0, 1}, {1, 0, 0}, {0, 1, 0}, 0}));
  EXPECT_FALSE(f.misses_triangle({{-5, 0, 2}, {10, 0, 0}, {0, 1, 0}, 0}));  // spans the beam
}

TEST(Frustum, OfRaysFromSeveralOriginsCullsNothing) {
  std::vector<Ray> rays = square_beam();
  rays[2].origin = {0, 0, 1e-12};
  const Frustum f(rays, {0, 1, 2, 3});
  EXPECT_EQ(f.planes(), 0);
  EXPECT_FALSE(f.misses_box({3, -1, 1}, {4, 1, 2}));
}

// Beams of 4x4 pixels on five scenes, 102 400 primary rays each, and beams of 1, 3 and 8
// on an image whose sides are no multiple of them: every hit, primitive and t, equal to
// the BVH's ray by ray; and the beams save node tests.
TEST(Beams, GiveEveryRayItsOwnHit) {
  struct Case {
    const char* scene;
    int width, height, beam;
  };
  for (const Case& c : {Case{"cornell", 320, 320, 4}, Case{"scenes/bunny.json", 320, 320, 4},
                        Case{"balls:1", 320, 320, 4}, Case{"stadium", 320, 320, 4},
                        Case{"scattered:3000", 320, 320, 4}, Case{"cornell", 101, 67, 3},
                        Case{"scenes/bunny.json", 101, 67, 8}, Case{"balls:1", 101, 67, 1}}) {
    const Scene scene = resolve_scene(c.scene);
    const TriangleSet triangles(scene);
    const Bvh bvh(triangles);
    const std::vector<Ray> rays = primary_rays(scene, c.width, c.height);
    BeamCost beam_cost;
    const std::vector<Hit> beams = trace_primary_beams(bvh, rays, c.width, c.height, c.beam, beam_cost);
    RayCost alone;
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Hit expected = bvh.closest_hit(rays[i], alone);
      ASSERT_EQ(beams[i].prim, expected.prim) << c.scene << " beam " << c.beam << " ray " << i;
      ASSERT_EQ(beams[i].t, expected.t) << c.scene << " beam " << c.beam << " ray " << i;
      hits += expected.hit();
    }
    EXPECT_GT(hits, rays.size() / 10) << c.scene;
    if (c.beam > 1) {
      EXPECT_LT(beam_cost.ray_nodes, alone.nodes) << c.scene;
    }
  }
}

TEST(Beams, RejectABeamOfMoreThan64Rays) {
  const Scene scene = resolve_scene("tetra:2");
  const TriangleSet triangles(scene);
  const Bvh bvh(triangles);
  const std::vector<Ray> rays = primary_rays(scene, 16, 16);
  BeamCost cost;
  EXPECT_THROW(trace_primary_beams(bvh, rays, 16, 16, 9, cost), Error);
}

}  // namespace
}  // namespace rpu::accel
