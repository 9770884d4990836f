// What every structure shares: the ray/triangle test, the triangles it skips, empty
// scenes, the closest-hit tie rule, and the byte model of its counters.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "accel/brute_force.hpp"
#include "accel/bsp.hpp"
#include "accel/bvh.hpp"
#include "accel/kd_tree.hpp"
#include "accel/octree.hpp"
#include "accel/structure.hpp"
#include "accel/uniform_grid.hpp"
#include "common/error.hpp"
#include "scene/resolve.hpp"

namespace rpu::accel {
namespace {

Triangle unit_triangle_at_z(double z) { return {{0.0, 0.0, z}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 0}; }

TEST(SharedTriangleTest, FindsTheAnalyticDistance) {
  double t = 0.0;
  ASSERT_TRUE(intersect({{0.25, 0.25, 5.0}, {0.0, 0.0, -1.0}}, unit_triangle_at_z(2.0), t));
  EXPECT_EQ(t, 3.0);
  ASSERT_TRUE(intersect({{0.25, 0.25, 5.0}, {0.0, 0.0, -2.0}}, unit_triangle_at_z(2.0), t));
  EXPECT_EQ(t, 1.5);  // t in units of the direction
}

TEST(SharedTriangleTest, CountsEdgesAndKeepsTheOpenInterval) {
  double t = 0.0;
  EXPECT_TRUE(intersect({{0.5, 0.5, 1.0}, {0.0, 0.0, -1.0}}, unit_triangle_at_z(0.0), t));   // on the hypotenuse
  EXPECT_TRUE(intersect({{0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}}, unit_triangle_at_z(0.0), t));   // on a vertex
  EXPECT_FALSE(intersect({{0.6, 0.6, 1.0}, {0.0, 0.0, -1.0}}, unit_triangle_at_z(0.0), t));  // outside
  EXPECT_FALSE(intersect({{0.2, 0.2, 1.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, unit_triangle_at_z(0.0), t));  // t = t_max
  EXPECT_FALSE(intersect({{0.2, 0.2, 1.0}, {0.0, 0.0, -1.0}, 1.0}, unit_triangle_at_z(0.0), t));       // t = t_min
  EXPECT_FALSE(intersect({{0.2, 0.2, 0.0}, {1.0, 0.0, 0.0}}, unit_triangle_at_z(0.0), t));  // in the plane
  EXPECT_FALSE(intersect({{0.2, 0.2, 1.0}, {0.0, 0.0, std::numeric_limits<double>::quiet_NaN()}},
                         unit_triangle_at_z(0.0), t));
}

// Two triangles in one plane sharing an edge, a ray through the edge: both give the
// same t, and every structure names the smaller id.
TEST(Structures, BreakTiesOfEqualTByTheSmallerPrimitiveId) {
  Scene s;
  s.materials.push_back({});
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.triangles = {{0, 2, 3}, {0, 1, 2}};  // the shared edge is the diagonal 0-2
  s.material_ids = {0, 0};
  const TriangleSet triangles(s);
  const Ray r{{0.5, 0.5, 1.0}, {0.0, 0.0, -1.0}};
  for (const std::string& name : structure_names()) {
    const auto st = build_structure(name, triangles, {});
    RayCost cost;
    const Hit h = st->closest_hit(r, cost);
    EXPECT_EQ(h.prim, 0u) << name;
    EXPECT_EQ(h.t, 1.0) << name;
  }
}

TEST(Structures, AnEmptySceneIsMissedByEveryRay) {
  Scene s;
  const TriangleSet triangles(s);
  for (const std::string& name : structure_names()) {
    const auto st = build_structure(name, triangles, {});
    RayCost cost;
    EXPECT_FALSE(st->closest_hit({{0, 0, 0}, {0, 0, 1}}, cost).hit()) << name;
    EXPECT_FALSE(st->any_hit({{0, 0, 0}, {0, 0, 1}}, cost)) << name;
    EXPECT_EQ(cost.tests, 0u) << name;
    EXPECT_EQ(st->node_count(), 0u) << name;
    EXPECT_EQ(st->memory_bytes(), 0u) << name;
  }
}

// A scene built in code may hold what the loader drops: every structure skips the same
// triangles, so a ray through them finds the one valid triangle behind.
TEST(Structures, SkipDegenerateNonFiniteAndOutOfRangeTrianglesAlike) {
  Scene s;
  s.materials.push_back({});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},       // 0: valid, z = 0
                 {0, 0, 1}, {1, 1, 1}, {2, 2, 1},       // 1: collinear, zero area
                 {0, 0, 2}, {nan, 0, 2}, {0, 1, 2}};    // 2: a NaN vertex
  s.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {0, 1, 99}};  // 3: an index out of range
  s.material_ids = {0, 0, 0, 0};
  const TriangleSet triangles(s);
  EXPECT_EQ(triangles.size(), 1u);
  EXPECT_EQ(triangles.skipped(), 3u);
  for (const std::string& name : structure_names()) {
    const auto st = build_structure(name, triangles, {});
    RayCost cost;
    const Hit h = st->closest_hit({{0.25, 0.25, 3.0}, {0.0, 0.0, -1.0}}, cost);
    EXPECT_EQ(h.prim, 0u) << name;
    EXPECT_EQ(h.t, 3.0) << name;
  }
}

TEST(Structures, UnknownNameIsAnError) {
  Scene s;
  const TriangleSet triangles(s);
  EXPECT_THROW(build_structure("octree-of-doom", triangles, {}), Error);
}

// The counters follow each structure's stated byte model.
TEST(Structures, CountBytesByTheirByteModel) {
  const Scene s = resolve_scene("tetra:3");
  const TriangleSet triangles(s);
  const Ray r{{0.05, 0.1, 5.0}, {0.0, 0.0, -1.0}};

  RayCost brute;
  BruteForce(triangles).closest_hit(r, brute);
  EXPECT_EQ(brute.tests, triangles.size());
  EXPECT_EQ(brute.bytes, triangles.size() * kTriangleRecordBytes);

  RayCost bvh;
  Bvh(triangles).closest_hit(r, bvh);
  EXPECT_GT(bvh.nodes, 0u);
  EXPECT_EQ(bvh.bytes, bvh.nodes * Bvh::kNodeBytes + bvh.tests * kTriangleRecordBytes);

  RayCost kd;
  KdTreeStructure(triangles).closest_hit(r, kd);
  EXPECT_GT(kd.nodes, 0u);
  EXPECT_EQ(kd.bytes, kd.nodes * KdTreeStructure::kNodeBytes + kd.tests * (kReferenceBytes + kTriangleRecordBytes));

  for (const OctreeSplit split : {OctreeSplit::kMidpoint, OctreeSplit::kCost}) {
    RayCost octree;
    const Octree tree(triangles, split);
    tree.closest_hit(r, octree);
    EXPECT_GT(octree.nodes, 0u);
    EXPECT_EQ(octree.bytes, octree.nodes * tree.node_bytes() + octree.tests * (kReferenceBytes + kTriangleRecordBytes));
  }

  RayCost bsp;
  Bsp(triangles).closest_hit(r, bsp);
  EXPECT_GT(bsp.nodes, 0u);
  EXPECT_EQ(bsp.bytes, bsp.nodes * Bsp::kNodeBytes + bsp.tests * (kReferenceBytes + kTriangleRecordBytes));

  // Without mailboxes every reference read is a test.
  RayCost grid;
  UniformGrid(triangles, 4.0, false).closest_hit(r, grid);
  EXPECT_GT(grid.nodes, 0u);
  EXPECT_EQ(grid.bytes,
            grid.nodes * UniformGrid::kCellRecordBytes + grid.tests * (kReferenceBytes + kTriangleRecordBytes));
}

// Many triangles around one point (a fan).
Scene fan() {
  Scene s;
  s.materials.push_back({});
  s.positions.emplace_back(0.0f, 0.0f, 0.0f);
  for (int i = 0; i < 40; ++i) {
    const float a = 0.157f * static_cast<float>(i);
    s.positions.emplace_back(std::cos(a), std::sin(a), 0.3f);
  }
  for (std::uint32_t i = 1; i <= 40; ++i) {
    s.triangles.emplace_back(0u, i, i % 40 + 1);
    s.material_ids.push_back(0);
  }
  return s;
}

// Rays down through the fan's centre and around it: brute force's answers.
void expect_fan_answers(const Structure& s, const TriangleSet& triangles) {
  const BruteForce brute(triangles);
  for (const double x : {0.0, 1e-4, -0.3, 0.5}) {
    const Ray r{{x, 0.01, 1.0}, {0.0, 0.0, -1.0}};
    RayCost cost;
    const Hit got = s.closest_hit(r, cost), expected = brute.closest_hit(r, cost);
    EXPECT_EQ(got.prim, expected.prim) << s.name() << " " << x;
    EXPECT_EQ(got.t, expected.t) << s.name() << " " << x;
  }
}

// A tree built over the fan stops at its depth limit around the fan's centre, with fewer
// than `most_nodes` nodes (it splits only there), and answers as brute force does.
template <typename Tree>
void expect_stopped_at_depth_around_the_fan(std::uint64_t most_nodes) {
  const TriangleSet triangles(fan());
  const Tree tree(triangles);
  EXPECT_EQ(tree.depth(), Tree::kMaxDepth) << tree.name();
  EXPECT_LT(tree.node_count(), most_nodes) << tree.name();
  expect_fan_answers(tree, triangles);
}

TEST(Octree, StopsAtItsDepthWhereTrianglesCannotBeSeparated) {
  expect_stopped_at_depth_around_the_fan<Octree>(8u * 8u * Octree::kMaxDepth);
}

// The BSP halves x, y and z in turn. The centre lies on the first planes, so up to four
// boxes of a level touch it; a full tree of depth 30 would have 2^31 nodes.
TEST(Bsp, StopsAtItsDepthWhereTrianglesCannotBeSeparated) {
  expect_stopped_at_depth_around_the_fan<Bsp>(8u * 4u * Bsp::kMaxDepth);
}

// Octree-R's root plane on x, worked by hand: 200 small triangles in x in [0, 0.2] and
// one at x = 1. The cost SA(low) N(low) + SA(high) N(high) falls as the plane moves left
// while every cluster triangle stays on the low side alone; the first candidate (k/32)
// past 0.2 is 7/32. The midpoint octree splits at 1/2.
TEST(Octree, OctreeRPlacesItsPlaneByCost) {
  Scene s;
  s.materials.push_back({});
  auto add = [&](float x, float y, float z, float size) {
    const auto v = static_cast<std::uint32_t>(s.positions.size());
    s.positions.insert(s.positions.end(), {{x, y, z}, {x + size, y, z}, {x, y + size, z + size}});
    s.triangles.emplace_back(v, v + 1, v + 2);
    s.material_ids.push_back(0);
  };
  for (int i = 0; i < 200; ++i) add(0.19f * float(i % 7) / 6.0f, float(i) / 200.0f, float(i % 13) / 13.0f, 0.01f);
  add(0.99f, 0.5f, 0.5f, 0.01f);
  const TriangleSet triangles(s);
  const Octree r(triangles, OctreeSplit::kCost), midpoint(triangles, OctreeSplit::kMidpoint);
  const double lo = triangles.bounds().lo.x, hi = triangles.bounds().hi.x;
  EXPECT_NEAR(r.root_planes().x, lo + (hi - lo) * 7.0 / 32.0, 1e-6);
  EXPECT_NEAR(midpoint.root_planes().x, 0.5 * (lo + hi), 1e-6);
  EXPECT_EQ(r.name(), "octree-r");
  EXPECT_EQ(midpoint.name(), "octree");
}

TEST(Bvh, SplitsTrianglesWithOneCentroidAtTheMedian) {
  // Every centroid in one place: no SAH plane separates them, the median split must.
  Scene s;
  s.materials.push_back({});
  for (int i = 0; i < 5000; ++i) {
    const float r = 1.0f + 0.001f * static_cast<float>(i);
    s.positions.insert(s.positions.end(), {{-r, -r, 0.0f}, {r, -r, 0.0f}, {0.0f, r, 0.0f}});
    const auto v = static_cast<std::uint32_t>(3 * i);
    s.triangles.emplace_back(v, v + 1, v + 2);
    s.material_ids.push_back(0);
  }
  const TriangleSet triangles(s);
  const Bvh bvh(triangles);
  EXPECT_LE(bvh.depth(), 12);  // log2(5000 / 8) levels of halving
  // Every triangle is met near t = 1, rounded differently: brute force decides which.
  const Ray r{{0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}};
  RayCost cost;
  const Hit h = bvh.closest_hit(r, cost), expected = BruteForce(triangles).closest_hit(r, cost);
  EXPECT_EQ(h.prim, expected.prim);
  EXPECT_EQ(h.t, expected.t);
}

}  // namespace
}  // namespace rpu::accel
