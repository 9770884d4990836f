#include "agreement.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <fmt/format.h>

#include "accel/brute_force.hpp"
#include "accel/ray_sets.hpp"
#include "accel/structure.hpp"
#include "common/random_vector.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel::test {

Scene scene_named(const std::string& name) { return resolve_scene(name); }

Scene teapot_in_a_stadium() {
  Scene s = resolve_scene("tetra:6");
  s.source = "teapot in a stadium";
  const auto first = static_cast<std::uint32_t>(s.positions.size());
  for (int x : {-1000, 1000}) {
    for (int y : {-1000, 1000}) {
      for (int z : {-1000, 1000}) s.positions.emplace_back(x, y, z);
    }
  }
  // The stadium: a cube of 12 triangles, vertex first + 4*(x>0) + 2*(y>0) + (z>0).
  const glm::uvec3 faces[] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                              {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const glm::uvec3& f : faces) {
    s.triangles.push_back(f + first);
    s.material_ids.push_back(0);
  }
  if (!s.normals.empty()) s.normals.resize(s.positions.size(), glm::vec3(0, 0, 1));
  if (!s.uvs.empty()) s.uvs.resize(s.positions.size(), glm::vec2(0));
  s.camera.position = {0.0, 0.5, 4.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  return s;
}

Scene scattered_triangles(int count, unsigned seed) {
  Scene s;
  s.source = fmt::format("{} scattered triangles", count);
  s.materials.push_back({});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> position(0.0, 1.0), offset(-0.04, 0.04);
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 centre = random_vector(position, rng);
    for (int k = 0; k < 3; ++k) s.positions.emplace_back(centre + random_vector(offset, rng));
    const auto v = static_cast<std::uint32_t>(3 * i);
    s.triangles.emplace_back(v, v + 1, v + 2);
    s.material_ids.push_back(0);
  }
  s.camera.position = {0.5, 0.6, 3.0};
  s.camera.look_at = {0.5, 0.5, 0.5};
  Light light;
  light.position = {2.0, 3.0, 2.0};
  s.lights.push_back(light);
  return s;
}

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
