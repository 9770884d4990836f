#include "agreement.hpp"

#include <vector>

#include <gtest/gtest.h>
#include <fmt/format.h>

#include "accel/brute_force.hpp"
#include "accel/ray_sets.hpp"
#include "accel/structure.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel::test {

Scene scene_named(const std::string& name) { return resolve_scene(name); }

void expect_agreement(const AgreementCase& c) {
  const Scene scene = c.scene();
  const TriangleSet triangles(scene);
  const BruteForce brute(triangles);
  RayCost cost;

  std::vector<Ray> rays = primary_rays(scene, c.width, c.height);
  std::vector<Hit> expected;
  expected.reserve(rays.size());
  for (const Ray& r : rays) expected.push_back(brute.closest_hit(r, cost));
  const std::vector<Ray> shadows = shadow_rays(scene, triangles, rays, expected, 7);
  const std::vector<Ray> randoms = random_rays(triangles, c.random, 11);
  for (const std::vector<Ray>* more : {&shadows, &randoms}) {
    for (const Ray& r : *more) {
      rays.push_back(r);
      expected.push_back(brute.closest_hit(r, cost));
    }
  }
  ASSERT_GE(rays.size(), c.min_rays) << "primary " << c.width * c.height << ", shadow " << shadows.size()
                                     << ", random " << randoms.size();
  ASSERT_FALSE(shadows.empty());
  std::size_t hits = 0;
  for (const Hit& h : expected) hits += h.hit();
  ASSERT_GT(hits, rays.size() / 10) << "too few rays hit anything to compare";

  // Brute force's own any hit on a share of the rays: the same answer as its closest hit.
  for (std::size_t i = 0; i < rays.size(); i += 16) {
    ASSERT_EQ(brute.any_hit(rays[i], cost), expected[i].hit()) << "ray " << i;
  }
  StructureOptions options;
  for (const std::string& name : structure_names()) {
    if (name == "brute") continue;
    const auto s = build_structure(name, triangles, options);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Ray& r = rays[i];
      const Hit got = s->closest_hit(r, cost);
      const bool any = s->any_hit(r, cost);
      const std::string ray = fmt::format("{} ray {} of {}: origin ({:.17g}, {:.17g}, {:.17g}) direction ({:.17g}, "
                                          "{:.17g}, {:.17g}) t in ({:.17g}, {:.17g})",
                                          name, i, rays.size(), r.origin.x, r.origin.y, r.origin.z, r.direction.x,
                                          r.direction.y, r.direction.z, r.t_min, r.t_max);
      ASSERT_EQ(got.prim, expected[i].prim) << ray << "; t " << got.t << ", brute force " << expected[i].t;
      ASSERT_EQ(got.t, expected[i].t) << ray;
      ASSERT_EQ(any, expected[i].hit()) << ray;
    }
  }
}

}  // namespace rpu::accel::test
