// Bounding volumes of objects: Ritter's sphere against CGAL's minimum enclosing sphere
// (the oracle), the PCA box, and the objects a scene is cut into.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "accel/bounding_volumes.hpp"
#include "accel/minimum_sphere.hpp"
#include "common/random_vector.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel {
namespace {

std::vector<glm::dvec3> cube_corners() {
  std::vector<glm::dvec3> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return points;
}

TEST(MinimumSphere, OfACubesCornersIsItsCircumsphere) {
  const std::vector<glm::dvec3> corners = cube_corners();
  const Sphere s = minimum_sphere(corners);
  EXPECT_NEAR(s.radius, std::sqrt(3.0) / 2.0, 1e-12);
  EXPECT_NEAR(glm::length(s.centre - glm::dvec3(0.5)), 0.0, 1e-12);
}

TEST(RitterSphere, OfACubesCornersIsOptimal) {
  // The first pass's diameter runs corner to opposite corner: the circumsphere.
  const std::vector<glm::dvec3> corners = cube_corners();
  EXPECT_NEAR(ritter_sphere(corners).radius, std::sqrt(3.0) / 2.0, 1e-12);
}

// CGAL's sphere in double holds its points to this fraction of its radius: its
// support-set arithmetic rounds (at most 5.8e-9 on the spheres of balls:1).
constexpr double kCgalTolerance = 1e-7;

// Every object of four scenes: Ritter's sphere holds every point (exactly: its last pass
// measures the distances the way this test does) and is no smaller than CGAL's.
TEST(RitterSphere, HoldsEveryPointAndIsNoSmallerThanTheMinimum) {
  for (const char* name : {"cornell", "balls:1", "tetra:4", "scenes/bunny.json"}) {
    const std::vector<std::vector<glm::dvec3>> objects = scene_objects(resolve_scene(name));
    ASSERT_FALSE(objects.empty()) << name;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      const Sphere ritter = ritter_sphere(objects[o]), smallest = minimum_sphere(objects[o]);
      for (const glm::dvec3& p : objects[o]) {
        ASSERT_LE(glm::length(p - ritter.centre), ritter.radius) << name << " object " << o;
        ASSERT_LE(glm::length(p - smallest.centre), smallest.radius * (1.0 + kCgalTolerance)) << name << " object " << o;
      }
      EXPECT_GE(ritter.radius, smallest.radius * (1.0 - kCgalTolerance)) << name << " object " << o;
    }
  }
}

TEST(RitterSphere, OfRandomCloudsIsWithinAFewPercentOfTheMinimum) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int cloud = 0; cloud < 20; ++cloud) {
    std::vector<glm::dvec3> points(500);
    const glm::dvec3 stretch(1.0, 0.1 + 0.05 * cloud, 0.5);
    for (glm::dvec3& p : points) p = random_vector(unit, rng) * stretch;
    const double ratio = ritter_sphere(points).radius / minimum_sphere(points).radius;
    EXPECT_GE(ratio, 1.0 - 1e-12);
    EXPECT_LT(ratio, 1.3) << cloud;  // Ritter's bound in practice: 5-20% (Ericson 2005, 4.3.2)
  }
}

TEST(PcaBox, OfARotatedBoxFindsItsAxesAndExtents) {
  // The corners of a 4 x 2 x 1 box rotated about a skew axis: the PCA box is that box.
  const glm::dmat3 rotation(glm::dvec3(0.36, 0.48, -0.8), glm::dvec3(-0.8, 0.6, 0.0), glm::dvec3(0.48, 0.64, 0.6));
  std::vector<glm::dvec3> points;
  for (const glm::dvec3& c : cube_corners()) points.push_back(rotation * ((c - 0.5) * glm::dvec3(4.0, 2.0, 1.0)));
  const OrientedBox box = pca_box(points);
  EXPECT_NEAR(volume(box), 8.0, 1e-9);
  EXPECT_NEAR(glm::length(box.centre), 0.0, 1e-12);
  for (const glm::dvec3& p : points) {
    const glm::dvec3 along = glm::transpose(box.axes) * (p - box.centre);
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(along[a]), box.half[a] * (1.0 + 1e-12) + 1e-12);
  }
}

TEST(SymmetricEigenvectors, DiagonaliseTheMatrix) {
  const glm::dmat3 m(glm::dvec3(4.0, 1.0, -2.0), glm::dvec3(1.0, 3.0, 0.5), glm::dvec3(-2.0, 0.5, 1.0));
  glm::dvec3 values;
  const glm::dmat3 v = symmetric_eigenvectors(m, values);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(glm::length(m * v[c] - values[c] * v[c]), 0.0, 1e-12) << c;
    EXPECT_NEAR(glm::length(v[c]), 1.0, 1e-12) << c;
  }
  EXPECT_NEAR(values.x + values.y + values.z, 8.0, 1e-12);  // the trace
}

TEST(SceneObjects, AreTheClassesOfTrianglesSharingAVertex) {
  // cornell: the five walls meet at shared corners (one object), the two blocks, the
  // sphere; the lamp is a light, not triangles.
  const std::vector<std::vector<glm::dvec3>> cornell = scene_objects(resolve_scene("cornell"));
  EXPECT_EQ(cornell.size(), 4u);
  EXPECT_EQ(cornell[0].size(), 8u);  // the walls' 20 corners are the room's 8
  // balls:1: the floor and ten spheres.
  EXPECT_EQ(scene_objects(resolve_scene("balls:1")).size(), 11u);
}

}  // namespace
}  // namespace rpu::accel
