#pragma once

// Small hand-made scenes for tests: the expected values come from geometry and
// arithmetic done in the test, not from the code under test.
#include <cstdint>
#include <initializer_list>
#include <utility>

#include "scene/scene.hpp"

namespace rpu::test {

inline std::uint32_t add_material(Scene& scene, Material m) {
  scene.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(scene.materials.size() - 1);
}

inline void add_triangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, std::uint32_t material) {
  const auto base = static_cast<std::uint32_t>(scene.positions.size());
  scene.positions.insert(scene.positions.end(), {a, b, c});
  scene.triangles.push_back({base, base + 1, base + 2});
  scene.material_ids.push_back(material);
}

// An axis-aligned square in the plane z = `z`, facing +z (or -z if `facing_down`).
inline void add_square_z(Scene& scene, float half, float z, std::uint32_t material, bool facing_down = false) {
  const glm::vec3 a{-half, -half, z}, b{half, -half, z}, c{half, half, z}, d{-half, half, z};
  if (facing_down) {
    add_triangle(scene, a, c, b, material);
    add_triangle(scene, a, d, c, material);
  } else {
    add_triangle(scene, a, b, c, material);
    add_triangle(scene, a, c, d, material);
  }
}

// A camera on +z looking down -z at the origin; a 1x1 image's only pixel-centre ray
// is exactly (0, 0, -1).
inline Camera camera_down_z(double height = 5.0) {
  Camera c;
  c.position = {0.0, 0.0, height};
  c.look_at = {0.0, 0.0, 0.0};
  c.up = {0.0, 1.0, 0.0};
  c.vfov_degrees = 60.0;
  return c;
}

}  // namespace rpu::test
