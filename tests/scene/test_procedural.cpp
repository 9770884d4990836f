// Built-in scenes: triangle counts from the generators' formulas, published geometry,
// valid material ids and no degenerate triangles.
#include <cmath>
#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "common/error.hpp"
#include "scene/geometry.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

void expect_well_formed(const Scene& s) {
  ASSERT_EQ(s.material_ids.size(), s.triangles.size());
  EXPECT_TRUE(s.normals.empty() || s.normals.size() == s.positions.size());
  EXPECT_TRUE(s.uvs.empty() || s.uvs.size() == s.positions.size());
  std::size_t degenerate = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const glm::uvec3 t = s.triangles[i];
    ASSERT_LT(t.x, s.positions.size());
    ASSERT_LT(t.y, s.positions.size());
    ASSERT_LT(t.z, s.positions.size());
    ASSERT_LT(s.material_ids[i], s.materials.size());
    if (is_degenerate(s.positions[t.x], s.positions[t.y], s.positions[t.z])) ++degenerate;
  }
  EXPECT_EQ(degenerate, 0u);
  EXPECT_TRUE(s.warnings.empty());
}

// UV sphere of n columns: n(n-2) triangles (2n in the caps, 2n per inner band).
std::size_t sphere_triangles(std::size_t slices) { return slices * (slices - 2); }

TEST(Cornell, HasThePublishedBoxDimensions) {
  const Scene s = make_cornell_box();
  expect_well_formed(s);
  const Bounds box = scene_bounds(s);
  // Cornell's measured data: the box spans 0..556 x 0..548.8 x 0..559.2 mm.
  EXPECT_NEAR(box.lo.x, 0.0, 1e-4);
  EXPECT_NEAR(box.lo.y, 0.0, 1e-4);
  EXPECT_NEAR(box.lo.z, 0.0, 1e-4);
  EXPECT_NEAR(box.hi.x, 556.0, 1e-3);
  EXPECT_NEAR(box.hi.y, 548.8, 1e-3);
  EXPECT_NEAR(box.hi.z, 559.2, 1e-3);
  EXPECT_EQ(s.camera.position, glm::dvec3(278.0, 273.0, -800.0));
  EXPECT_NEAR(s.camera.vfov_degrees, 39.3077, 1e-4);  // 2 atan(12.5 / 35)
}

TEST(Cornell, CountsFiveWallsTwoBlocksAndTheSphere) {
  // 5 wall quads + 5 faces per block, two triangles each, plus the glass sphere.
  EXPECT_EQ(make_cornell_box().triangles.size(), 30 + sphere_triangles(32));
  EXPECT_EQ(make_cornell_box(8).triangles.size(), 30 + sphere_triangles(8));
}

TEST(Cornell, HasTheCeilingLampMirrorAndGlass) {
  const Scene s = make_cornell_box();
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& lamp = s.lights[0];
  EXPECT_EQ(lamp.kind, LightKind::kArea);
  const glm::dvec3 far_corner = lamp.position + lamp.edge_u + lamp.edge_v;
  EXPECT_EQ(glm::min(lamp.position, far_corner).x, 213.0);
  EXPECT_EQ(glm::max(lamp.position, far_corner).x, 343.0);
  EXPECT_EQ(glm::min(lamp.position, far_corner).z, 227.0);
  EXPECT_EQ(glm::max(lamp.position, far_corner).z, 332.0);
  EXPECT_LT(glm::cross(lamp.edge_u, lamp.edge_v).y, 0.0);  // emits downwards
  bool mirror = false, glass = false;
  for (const Material& m : s.materials) {
    mirror = mirror || m.reflectance >= 0.8;
    glass = glass || (m.ior == 1.5 && m.transmittance >= 0.8);
  }
  EXPECT_TRUE(mirror);
  EXPECT_TRUE(glass);
}

TEST(Balls, TriangleCountFollowsTheSphereCount) {
  std::size_t spheres = 0, level_count = 1;
  for (int levels = 0; levels <= 3; ++levels) {
    spheres += level_count;  // SPD: sum of 9^n for n = 0..size
    level_count *= 9;
    const Scene s = make_sphereflake(levels, 8);
    EXPECT_EQ(s.triangles.size(), spheres * sphere_triangles(8) + 2) << "levels " << levels;
  }
  EXPECT_EQ(spheres, 820u);
}

TEST(Balls, DefaultStaysUnder200kTriangles) {
  const Scene s = make_sphereflake();
  expect_well_formed(s);
  EXPECT_EQ(s.triangles.size(), 820 * sphere_triangles(16) + 2);
  EXPECT_LT(s.triangles.size(), 200000u);
  EXPECT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.camera.position, glm::dvec3(2.1, 1.3, 1.7));
  // The floor is the 24 x 24 square half a unit below the origin.
  const Bounds box = scene_bounds(s);
  EXPECT_FLOAT_EQ(static_cast<float>(box.lo.x), -12.0f);
  EXPECT_FLOAT_EQ(static_cast<float>(box.hi.y), 12.0f);
  EXPECT_FLOAT_EQ(static_cast<float>(box.lo.z), -0.5f);
}

TEST(Balls, ChildrenTouchTheirParentSixOnTheEquatorThreeAbove) {
  const Scene s = make_sphereflake(1, 8);
  const std::size_t per_sphere = 2 + (8 / 2 - 1) * 8;  // poles + rings
  const std::size_t first = 6;                         // the floor's two flat triangles
  ASSERT_EQ(s.positions.size(), first + 10 * per_sphere);
  int equator = 0, above = 0;
  for (std::size_t child = 1; child < 10; ++child) {
    glm::dvec3 center(0.0);
    for (std::size_t v = 0; v < per_sphere; ++v) {
      center += glm::dvec3(s.positions[first + child * per_sphere + v]);
    }
    center /= static_cast<double>(per_sphere);
    // Radius 0.5/3, touching the root of radius 0.5.
    EXPECT_NEAR(glm::length(center), 0.5 + 0.5 / 3.0, 1e-6);
    if (std::abs(center.z) < 1e-6) ++equator;
    if (center.z > 0.1) ++above;
  }
  EXPECT_EQ(equator, 6);
  EXPECT_EQ(above, 3);
}

TEST(Tetra, HasFourToTheLevelTriangles) {
  std::size_t expected = 1;
  for (int levels = 1; levels <= 6; ++levels) {
    expected *= 4;
    const Scene s = make_tetra(levels);
    expect_well_formed(s);
    EXPECT_EQ(s.triangles.size(), expected);
    const Bounds box = scene_bounds(s);
    EXPECT_EQ(box.lo, glm::dvec3(-1.0));
    EXPECT_EQ(box.hi, glm::dvec3(1.0));
  }
  EXPECT_EQ(make_tetra().triangles.size(), 4096u);
}

TEST(Stadium, IsTheTetraInsideACube2000Wide) {
  const Scene s = make_stadium(3);
  expect_well_formed(s);
  EXPECT_EQ(s.triangles.size(), 64u + 12u);
  const Bounds box = scene_bounds(s);
  EXPECT_EQ(box.lo, glm::dvec3(-1000.0));
  EXPECT_EQ(box.hi, glm::dvec3(1000.0));
  EXPECT_EQ(make_stadium().triangles.size(), 4096u + 12u);
}

TEST(Scattered, HasCountSmallTrianglesInTheUnitCube) {
  for (const int count : {1, 3000, 100000}) {
    const Scene s = make_scattered(count);
    expect_well_formed(s);
    EXPECT_EQ(s.triangles.size(), static_cast<std::size_t>(count));
    // Each vertex within 0.04 (3000 / count)^(1/3) of a centre in [0, 1)^3.
    const double reach = 0.04 * std::cbrt(3000.0 / count);
    const Bounds box = scene_bounds(s);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(box.lo[a], -reach - 1e-6) << count;
      EXPECT_LE(box.hi[a], 1.0 + reach + 1e-6) << count;
    }
  }
  // The same name is the same scene.
  EXPECT_EQ(make_scattered(50).positions, make_builtin_scene("scattered:50").positions);
}

TEST(Builtins, NamesCarryASize) {
  EXPECT_EQ(make_builtin_scene("balls:1").triangles.size(), 10 * sphere_triangles(16) + 2);
  EXPECT_EQ(make_builtin_scene("tetra:2").triangles.size(), 16u);
  EXPECT_EQ(resolve_scene("tetra:3").triangles.size(), 64u);
  EXPECT_EQ(resolve_scene("").source, "cornell");
  for (const std::string& name : builtin_scene_names()) {
    EXPECT_FALSE(make_builtin_scene(name).triangles.empty()) << name;
  }
}

TEST(Builtins, RejectBadNamesAndSizes) {
  auto message = [](const char* arg) {
    try {
      resolve_scene(arg);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("balls:x"), "balls:x: the size after ':' must be a whole number");
  EXPECT_NE(message("balls:9").find("size must be 0..5"), std::string::npos);
  EXPECT_NE(message("tetra:0").find("size must be 1..10"), std::string::npos);
  EXPECT_EQ(message("cornell:100000"), "cornell: sphere tessellation 100000 must be an even number in 4..1024");
  EXPECT_EQ(message("scattered:0"), "scattered:0: size must be 1..1000000 (triangles)");
  EXPECT_EQ(message("stadium:11"), "stadium:11: size must be 1..10 (the tetra's levels of recursion)");
  EXPECT_EQ(message("cornell:2"), "cornell: sphere tessellation 2 must be an even number in 4..1024");
  EXPECT_NE(message("teapot").find("teapot: no such scene: not a file, nor a built-in scene "
                                   "(cornell, balls, tetra"),
            std::string::npos);
}

}  // namespace
}  // namespace rpu
