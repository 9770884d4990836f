// The SAH kd-tree builder: structural invariants, statistics that add up, and coverage
// checked independently of the builder: points sampled on every triangle (in double),
// rounded into the number format the tree was built for, walk the tree by its split
// values rounded into that format (fp::soft compares) as a traversal would and must
// reach leaves that reference their triangle; a point exactly on a plane walks both sides.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "fp/soft.hpp"
#include "kdtree/kdtree.hpp"
#include "rpu/spec.hpp"
#include "scene/geometry.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"
#include "common/random_vector.hpp"

namespace rpu {
namespace {

struct Box {
  glm::dvec3 lo, hi;
};

double area(const Box& b) {
  const glm::dvec3 d = b.hi - b.lo;
  return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// A value as the units load it: to fp32, then rounded into the format (from_fp32).
std::uint32_t load(fp::Format f, double x) {
  return fp::soft::from_fp32(f, std::bit_cast<std::uint32_t>(static_cast<float>(x)));
}
double value(fp::Format f, std::uint32_t bits) {
  return std::bit_cast<float>(fp::soft::to_fp32(f, bits));
}

// Structure: indices in range, every node reached exactly once from the root with the
// below child right after its parent, depth within the limit, leaf lists in range;
// then the statistics recomputed here and compared.
void expect_valid_structure(const Scene& scene, const KdTree& tree, const KdBuildConfig& config) {
  ASSERT_FALSE(tree.nodes.empty());
  std::vector<int> seen(tree.nodes.size(), 0);
  struct Item {
    std::uint32_t index;
    Box box;
    int depth;
  };
  const Box root{glm::dvec3(tree.bounds_lo), glm::dvec3(tree.bounds_hi)};
  std::vector<Item> stack{{0, root, 0}};
  std::uint64_t leaves = 0, empty = 0, refs = 0;
  int max_depth = 0;
  double cost = 0.0;
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    ASSERT_LT(it.index, tree.nodes.size());
    ASSERT_EQ(seen[it.index]++, 0) << "node " << it.index << " reached twice";
    ASSERT_LE(it.depth, config.max_depth);
    max_depth = std::max(max_depth, it.depth);
    const KdNode n = tree.nodes[it.index];
    const double p = area(it.box) / area(root);
    if (n.is_leaf()) {
      ++leaves;
      empty += n.prim_count() == 0;
      refs += n.prim_count();
      ASSERT_LE(std::uint64_t{n.first_prim_ref()} + n.prim_count(), tree.prim_refs.size());
      for (std::uint32_t i = 0; i < n.prim_count(); ++i) {
        ASSERT_LT(tree.prim_refs[n.first_prim_ref() + i], scene.triangles.size());
      }
      cost += config.intersection_cost * p * n.prim_count();
      continue;
    }
    cost += config.traversal_cost * p;
    const int k = n.split_axis();
    ASSERT_GT(n.above_child(), it.index + 1);
    ASSERT_LT(n.above_child(), tree.nodes.size());
    ASSERT_GT(double(n.split()), it.box.lo[k]) << "split outside its node at node " << it.index;
    ASSERT_LT(double(n.split()), it.box.hi[k]) << "split outside its node at node " << it.index;
    Item below{it.index + 1, it.box, it.depth + 1}, above{n.above_child(), it.box, it.depth + 1};
    below.box.hi[k] = n.split();
    above.box.lo[k] = n.split();
    stack.push_back(above);
    stack.push_back(below);
  }
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "node " << i << " unreachable";

  const KdTreeStats& s = tree.stats;
  EXPECT_EQ(s.nodes, tree.nodes.size());
  EXPECT_EQ(s.leaves, leaves);
  EXPECT_EQ(s.empty_leaves, empty);
  EXPECT_EQ(s.max_depth, max_depth);
  EXPECT_EQ(s.prim_refs, tree.prim_refs.size());
  EXPECT_EQ(refs, tree.prim_refs.size()) << "leaf counts must add up to the reference list";
  EXPECT_EQ(s.bytes, 8 * s.nodes + 4 * s.prim_refs);
  EXPECT_NEAR(s.sah_cost, cost, 1e-9 * cost);
  EXPECT_GE(s.build_seconds, 0.0);
  EXPECT_GE(s.mean_leaf_depth, 0.0);
  EXPECT_LE(s.mean_leaf_depth, double(max_depth));
  if (leaves > empty) {
    EXPECT_DOUBLE_EQ(s.mean_prims_per_leaf, double(refs) / double(leaves - empty));
  }
  // The root box holds every vertex as the units load it (rounded into the format).
  for (const glm::vec3& v : scene.positions) {
    for (int k = 0; k < 3; ++k) {
      const double x = value(config.format, load(config.format, v[k]));
      EXPECT_LE(tree.bounds_lo[k], x);
      EXPECT_GE(tree.bounds_hi[k], x);
    }
  }
}

// Every split value and the root box load into the format unchanged, and no split is
// a subnormal of the format (which would load as zero).
void expect_exact_in_format(const KdTree& tree, fp::Format f) {
  std::size_t inexact = 0;
  for (const KdNode& n : tree.nodes) {
    if (n.is_leaf()) continue;
    const std::uint32_t loaded = fp::soft::from_fp32(f, n.split_bits());
    inexact += fp::soft::to_fp32(f, loaded) != n.split_bits();
  }
  EXPECT_EQ(inexact, 0u) << "split values that move when loaded into " << f.name();
  for (int k = 0; k < 3; ++k) {
    for (const float b : {tree.bounds_lo[k], tree.bounds_hi[k]}) {
      EXPECT_EQ(value(f, load(f, b)), b) << "root box value " << b << " is not exact in " << f.name();
    }
  }
}

// The leaves a point (coordinates already in the format) reaches, comparing in the
// format like a traversal: below when p < split, above when p > split, both when equal.
void leaves_at(const KdTree& tree, fp::Format f, const std::array<std::uint32_t, 3>& p,
               std::vector<std::uint32_t>& out) {
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const std::uint32_t i = stack.back();
    stack.pop_back();
    const KdNode n = tree.nodes[i];
    if (n.is_leaf()) {
      out.push_back(i);
      continue;
    }
    const std::uint32_t s = fp::soft::from_fp32(f, n.split_bits());
    const std::uint32_t x = p[static_cast<std::size_t>(n.split_axis())];
    if (fp::soft::le(f, x, s)) stack.push_back(i + 1);
    if (fp::soft::ge(f, x, s)) stack.push_back(n.above_child());
  }
}

// One ulp of the format at the largest vertex coordinate magnitude, the unit of the
// builder's margin (docs/kdtree.md), computed here from the rounded vertices.
double scene_ulp(const Scene& scene, fp::Format f) {
  double magnitude = 0.0;
  for (const glm::vec3& v : scene.positions) {
    for (int k = 0; k < 3; ++k) magnitude = std::max(magnitude, std::abs(value(f, load(f, v[k]))));
  }
  return std::ldexp(1.0, std::max(std::ilogb(magnitude), f.min_exponent()) - f.fraction_bits);
}

// Vertices, edge midpoints and `random_points` random barycentric points per triangle,
// each rounded into the tree's format. With a margin of K ulps each point is walked
// again moved by K - 2 ulps on every axis (random signs, the far corner of the margin
// box): rounding the point and the vertices into the format moves it by at most one ulp
// from the rounded triangle, and rounding the moved point by another half, so the
// moved point still lies within the margin the builder promises.
void expect_every_point_finds_its_triangle(const Scene& scene, const KdTree& tree, const KdBuildConfig& config,
                                           int random_points) {
  const fp::Format f = config.format;
  const double shift = config.margin_ulps >= 2 ? (config.margin_ulps - 2) * scene_ulp(scene, f) : 0.0;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint32_t> leaves;
  std::size_t failures = 0;
  for (std::uint32_t t = 0; t < scene.triangles.size() && failures < 10; ++t) {
    const glm::dvec3 a(scene.positions[scene.triangles[t][0]]), b(scene.positions[scene.triangles[t][1]]),
        c(scene.positions[scene.triangles[t][2]]);
    std::vector<glm::dvec3> points{a, b, c, (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5};
    for (int i = 0; i < random_points; ++i) {
      double s = u(rng), r = u(rng);
      if (s + r > 1.0) {
        s = 1.0 - s;
        r = 1.0 - r;
      }
      points.push_back(a + s * (b - a) + r * (c - a));
    }
    for (const glm::dvec3& exact : points) {
      const std::array<std::uint32_t, 3> rounded{load(f, exact.x), load(f, exact.y), load(f, exact.z)};
      std::array<std::uint32_t, 3> moved{};
      for (std::size_t k = 0; k < 3; ++k) {
        moved[k] = load(f, value(f, rounded[k]) + (u(rng) < 0.5 ? -shift : shift));
      }
      for (const std::array<std::uint32_t, 3>& p : {rounded, moved}) {
        leaves.clear();
        leaves_at(tree, f, p, leaves);
        for (const std::uint32_t leaf : leaves) {
          const KdNode n = tree.nodes[leaf];
          const auto first = tree.prim_refs.begin() + n.first_prim_ref();
          if (std::find(first, first + n.prim_count(), t) == first + n.prim_count()) {
            ADD_FAILURE() << f.name() << ": triangle " << t << " point (" << value(f, p[0]) << ", "
                          << value(f, p[1]) << ", " << value(f, p[2]) << ") reaches leaf " << leaf
                          << " which does not reference it";
            ++failures;
          }
        }
      }
    }
  }
}

std::string error_of(const Scene& s, const KdBuildConfig& c) {
  try {
    build_kdtree(s, c);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

bool add_triangle(Scene& s, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  if (is_degenerate(a, b, c)) return false;
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  s.positions.insert(s.positions.end(), {a, b, c});
  s.triangles.emplace_back(base, base + 1, base + 2);
  s.material_ids.push_back(0);
  return true;
}

// Random triangles of random size in the unit cube; with `grid`, vertices snap to
// multiples of 1/8 so that many triangles share coordinates, touch candidate planes
// exactly and lie in axis planes.
Scene random_soup(std::size_t n, bool grid, std::uint64_t seed) {
  Scene s;
  s.source = grid ? "grid soup" : "random soup";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto coord = [&](float centre, float size) {
    const float v = centre + size * (u(rng) - 0.5f);
    return grid ? std::round(v * 8.0f) / 8.0f : v;
  };
  while (s.triangles.size() < n) {
    const glm::vec3 centre = random_vector<glm::vec3>(u, rng);
    const float size = grid ? 0.5f : 0.2f * u(rng) * u(rng);
    glm::vec3 v[3];
    for (glm::vec3& p : v) p = {coord(centre.x, size), coord(centre.y, size), coord(centre.z, size)};
    // A third of the grid triangles lie in an axis plane.
    if (grid && s.triangles.size() % 3 == 0) v[1].y = v[2].y = v[0].y;
    add_triangle(s, v[0], v[1], v[2]);
  }
  return s;
}

Scene bunny_scene() {
  return resolve_scene((std::filesystem::path(RPU_SOURCE_DIR) / "scenes" / "bunny.json").string());
}

KdBuildConfig config(bool perfect, fp::Format format = fp::kFp32) {
  KdBuildConfig c = kd_build_config_for("default");
  c.perfect_splits = perfect;
  c.format = format;
  return c;
}

// The scene as the tree sees it: its vertices in the tree's kd space.
Scene in_kd_space(const Scene& scene, const KdTree& tree) {
  Scene kd = scene;
  for (glm::vec3& p : kd.positions) p = to_kd_space(p, tree.scale_exponent);
  return kd;
}

void check_scene(const Scene& scene, bool perfect, int random_points, fp::Format format = fp::kFp32) {
  SCOPED_TRACE(scene.source + (perfect ? " (perfect splits)" : "") + " for " + format.name());
  const KdBuildConfig c = config(perfect, format);
  const KdTree tree = build_kdtree(scene, c);
  const Scene kd = in_kd_space(scene, tree);
  expect_valid_structure(kd, tree, c);
  expect_exact_in_format(tree, format);
  expect_every_point_finds_its_triangle(kd, tree, c, random_points);
  EXPECT_LT(tree.stats.sah_cost, c.intersection_cost * double(scene.triangles.size()))
      << "the tree must beat a single leaf";
}

TEST(KdTree, CornellBoxIsValidAndCovered) {
  check_scene(make_cornell_box(), false, 32);
  check_scene(make_cornell_box(), true, 32);
}

// A format whose grid and rounding margin are coarser than the scene's triangles builds a
// tree of far higher SAH cost than fp32's, and the note says so, naming both trees; one
// that keeps the planes gets no note.
TEST(KdTree, LostPlanesAreNamed) {
  const Scene scene = make_sphereflake(2);
  const KdTreeStats fp32 = build_kdtree(scene, config(false)).stats;
  const KdTreeStats bf16 = build_kdtree(scene, config(false, fp::Format{8, 7})).stats;
  const KdTreeStats rpu24 = build_kdtree(scene, config(false, fp::Format{7, 16})).stats;
  EXPECT_GT(bf16.sah_cost, kLostPlanesRatio * fp32.sah_cost);
  const std::string note = lost_planes_note("bf16", bf16, fp32);
  EXPECT_NE(note.find("bf16 cannot place the planes"), std::string::npos) << note;
  EXPECT_NE(note.find(fmt::format("{} nodes", bf16.nodes)), std::string::npos) << note;
  EXPECT_NE(note.find(fmt::format("fp32's {} nodes", fp32.nodes)), std::string::npos) << note;
  EXPECT_EQ(lost_planes_note("rpu24", rpu24, fp32), "") << "rpu24's SAH cost " << rpu24.sah_cost;
}

TEST(KdTree, SphereflakeIsValidAndCovered) {
  check_scene(make_sphereflake(2), false, 8);
  check_scene(make_sphereflake(2), true, 8);
}

TEST(KdTree, RandomSoupIsValidAndCovered) {
  check_scene(random_soup(3000, false, 1), false, 8);
  check_scene(random_soup(3000, false, 2), true, 8);
}

TEST(KdTree, GridSoupWithSharedCoordinatesIsValidAndCovered) {
  check_scene(random_soup(2000, true, 3), false, 8);
  check_scene(random_soup(2000, true, 4), true, 8);
}

TEST(KdTree, BunnyIsValidAndCovered) {
  const Scene bunny = bunny_scene();
  check_scene(bunny, false, 4);
  check_scene(bunny, true, 4);
}

// Every spec format (spec/formats.toml): trees built for it hold only splits exact in
// it, and points walked in it find their triangles, on scenes with shared vertices,
// coordinates on a grid, axis-aligned triangles and curved meshes.
class KdTreeFormat : public ::testing::TestWithParam<spec::FormatSpec> {};

TEST_P(KdTreeFormat, TreesForTheFormatAreExactAndCovered) {
  const fp::Format f = fp::format_by_name(GetParam().name);
  check_scene(make_cornell_box(), true, 8, f);
  check_scene(make_sphereflake(1), true, 4, f);
  check_scene(random_soup(1000, true, 10), false, 8, f);
  check_scene(random_soup(1000, true, 11), true, 8, f);
  check_scene(random_soup(1000, false, 12), true, 8, f);
  check_scene(bunny_scene(), true, 2, f);
}

INSTANTIATE_TEST_SUITE_P(SpecFormats, KdTreeFormat, ::testing::ValuesIn(spec::kFormats),
                         [](const ::testing::TestParamInfo<spec::FormatSpec>& param) {
                           return std::string(param.param.name);
                         });

// A hardware configuration's format reaches the builder, so a tree for the 24-bit
// rpu2005 is not the fp32 tree: the fp32 tree of the bunny holds splits that move when
// loaded into rpu24, the rpu24 tree none.
TEST(KdTree, ConfigForTakesTheHardwareFormat) {
  for (const spec::HardwareConfig& h : spec::kConfigs) {
    EXPECT_EQ(kd_build_config_for(std::string(h.name)).format, fp::format_by_name(h.format)) << h.name;
  }
  const fp::Format rpu24 = fp::format_by_name("rpu24");
  ASSERT_EQ(kd_build_config_for("rpu2005").format, rpu24);
  EXPECT_EQ(kd_build_config_for("default").format, fp::kFp32);
  const Scene bunny = bunny_scene();
  const auto moved = [&](const KdTree& tree) {
    std::size_t count = 0;
    for (const KdNode& n : tree.nodes) {
      count += !n.is_leaf() && fp::soft::to_fp32(rpu24, fp::soft::from_fp32(rpu24, n.split_bits())) != n.split_bits();
    }
    return count;
  };
  EXPECT_GT(moved(build_kdtree(bunny, kd_build_config_for("default"))), 0u);
  EXPECT_EQ(moved(build_kdtree(bunny, kd_build_config_for("rpu2005"))), 0u);
}

// Kd space puts the largest coordinate magnitude in [32, 64) (kdtree.hpp), the same for a
// scene scaled by any power of two: the tree is the same, and a scene far beyond a
// narrow format's range builds for it.
TEST(KdTree, KdSpaceDoesNotDependOnTheSceneScale) {
  const Scene base = make_cornell_box();
  const KdTree reference = build_kdtree(base, config(true));
  EXPECT_EQ(reference.scale_exponent, 9 - kKdMagnitudeExponent) << "the Cornell box spans 0 to about 559";
  for (int k : {-100, -60, -1, 1, 60, 100}) {
    Scene scaled = base;
    for (glm::vec3& p : scaled.positions) p *= std::ldexp(1.0f, k);
    const KdTree tree = build_kdtree(scaled, config(true));
    EXPECT_EQ(tree.scale_exponent, reference.scale_exponent + k) << "k " << k;
    EXPECT_EQ(tree.bounds_lo, reference.bounds_lo) << "k " << k;
    EXPECT_EQ(tree.bounds_hi, reference.bounds_hi) << "k " << k;
    EXPECT_EQ(tree.prim_refs, reference.prim_refs) << "k " << k;
    ASSERT_EQ(tree.nodes.size(), reference.nodes.size()) << "k " << k;
    for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
      ASSERT_EQ(tree.nodes[i].word0, reference.nodes[i].word0) << "k " << k << " node " << i;
      ASSERT_EQ(tree.nodes[i].word1, reference.nodes[i].word1) << "k " << k << " node " << i;
    }
  }
  float magnitude = 0.0f;
  for (int k = 0; k < 3; ++k) {
    magnitude = std::max({magnitude, std::abs(reference.bounds_lo[k]), std::abs(reference.bounds_hi[k])});
  }
  EXPECT_EQ(std::ilogb(magnitude), kKdMagnitudeExponent);
  Scene big;
  big.source = "big.json";
  add_triangle(big, {0, 0, 0}, {70000, 0, 0}, {0, 50000, 20000});
  const KdBuildConfig fp16 = config(true, fp::format_by_name("fp16"));
  const KdTree tree = build_kdtree(big, fp16);
  expect_valid_structure(in_kd_space(big, tree), tree, fp16);
  expect_exact_in_format(tree, fp16.format);
  expect_every_point_finds_its_triangle(in_kd_space(big, tree), tree, fp16, 8);
}

TEST(KdTree, RefusesAMarginBeyondTheFormatRange) {
  // E2M1's largest finite value is 3; 4 of its ulps at magnitude 1.5 are 2.
  Scene edge;
  edge.source = "edge.json";
  add_triangle(edge, {0, 0, 0}, {1.5f, 0, 0}, {0, 1, 0});
  EXPECT_EQ(error_of(edge, config(false, fp::format_by_name("E2M1"))),
            "scene 'edge.json': coordinates up to 1.5 plus the kd-tree margin of 4 ulps exceed the range of number "
            "format E2M1; lower the margin or choose a wider format");
  KdBuildConfig c = config(false, fp::format_by_name("E2M1"));
  c.margin_ulps = 0;
  EXPECT_EQ(error_of(edge, c), "no error");
}

TEST(KdTree, RefusesNonFiniteVertices) {
  Scene s;
  s.source = "nan.json";
  add_triangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  s.positions[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(error_of(s, config(false)), "scene 'nan.json': vertex 1 coordinate nan is not finite; fix the geometry");
}

TEST(KdTree, SingleTriangleIsOneLeaf) {
  Scene s;
  s.source = "one triangle";
  add_triangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const KdTree tree = build_kdtree(s, config(false));
  ASSERT_EQ(tree.nodes.size(), 1u);
  EXPECT_TRUE(tree.nodes[0].is_leaf());
  EXPECT_EQ(tree.nodes[0].prim_count(), 1u);
  EXPECT_EQ(tree.prim_refs, std::vector<std::uint32_t>{0});
  EXPECT_EQ(tree.scale_exponent, -kKdMagnitudeExponent);  // the largest coordinate, 1, becomes 32
  EXPECT_EQ(tree.bounds_lo, glm::vec3(0, 0, 0));
  EXPECT_EQ(tree.bounds_hi, glm::vec3(32, 32, 0));
  EXPECT_DOUBLE_EQ(tree.stats.sah_cost, 20.0);
}

// Hand-worked SAH: two unit squares (two triangles each) at x in [0,1] and [9,10] in a
// 10 x 1 x 1 box. The cheapest plane cuts the empty gap next to one square; the tree
// separates the squares and leaves the gap empty.
TEST(KdTree, TwoDistantSquaresAreSeparated) {
  Scene s;
  s.source = "two squares";
  for (const float x0 : {0.0f, 9.0f}) {
    add_triangle(s, {x0, 0, 0}, {x0 + 1, 0, 1}, {x0, 1, 1});
    add_triangle(s, {x0 + 1, 1, 0}, {x0 + 1, 0, 1}, {x0, 1, 1});
  }
  KdBuildConfig c = config(false);
  const KdTree tree = build_kdtree(s, c);
  expect_valid_structure(in_kd_space(s, tree), tree, c);
  expect_every_point_finds_its_triangle(in_kd_space(s, tree), tree, c, 16);
  ASSERT_FALSE(tree.nodes[0].is_leaf());
  EXPECT_EQ(tree.nodes[0].split_axis(), 0);
  // Every reference is to one square only: no leaf mixes triangles 0-1 with 2-3.
  for (const KdNode& n : tree.nodes) {
    if (!n.is_leaf() || n.prim_count() == 0) continue;
    const auto first = tree.prim_refs.begin() + n.first_prim_ref();
    const bool left = *first < 2;
    for (std::uint32_t i = 0; i < n.prim_count(); ++i) EXPECT_EQ(first[i] < 2, left);
  }
  EXPECT_EQ(tree.stats.prim_refs, 4u);
}

TEST(KdTree, CoincidentTrianglesTerminate) {
  Scene s = random_soup(200, false, 5);
  s.source = "coincident";
  for (int i = 0; i < 3000; ++i) add_triangle(s, {0.5f, 0.5f, 0.5f}, {0.51f, 0.5f, 0.5f}, {0.5f, 0.51f, 0.5f});
  KdBuildConfig c = config(false);
  c.max_depth = c.stack_depth = 12;
  c.traversal_cost = 0.0;  // splitting looks free: only the depth limit and the cost stop it
  const KdTree tree = build_kdtree(s, c);
  expect_valid_structure(in_kd_space(s, tree), tree, c);
  EXPECT_LE(tree.stats.max_depth, 12);
  // The 3000 copies stay together in some leaf.
  bool found = false;
  for (const KdNode& n : tree.nodes) found |= n.is_leaf() && n.prim_count() >= 3000;
  EXPECT_TRUE(found);
}

TEST(KdTree, CoincidentTrianglesAloneMakeOneLeaf) {
  Scene s;
  s.source = "stack of copies";
  for (int i = 0; i < 1000; ++i) add_triangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 1});
  const KdTree tree = build_kdtree(s, config(false));
  EXPECT_EQ(tree.nodes.size(), 1u) << "no split of identical triangles is cheaper than a leaf";
}

TEST(KdTree, BuildsAsDeepAsTheStackAllows) {
  const Scene s = random_soup(20000, false, 6);
  KdBuildConfig c = config(false);
  c.stack_depth = 8;
  c.max_depth = 8;
  const KdTree tree = build_kdtree(s, c);
  expect_valid_structure(in_kd_space(s, tree), tree, c);
  EXPECT_EQ(tree.stats.max_depth, 8);
  c.max_depth = 9;
  try {
    build_kdtree(s, c);
    FAIL() << "a tree deeper than the stack must be refused";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "kd-tree max depth 9 exceeds the traversal stack depth 8 of config 'default'; "
                 "lower --kd-depth or choose a config with a deeper stack");
  }
}

TEST(KdTree, RefusesImpossibleConfigurations) {
  const Scene s = random_soup(10, false, 8);
  KdBuildConfig c = config(false);
  c.max_depth = 40;
  EXPECT_EQ(error_of(s, c),
            "kd-tree max depth 40 exceeds the traversal stack depth 32 of config 'default'; "
            "lower --kd-depth or choose a config with a deeper stack");
  c = config(false);
  c.max_depth = -1;
  EXPECT_NE(error_of(s, c).find("max depth -1 is outside [0, 64]"), std::string::npos) << error_of(s, c);
  c = config(false);
  c.stack_depth = c.max_depth = 65;
  EXPECT_NE(error_of(s, c).find("max depth 65 is outside [0, 64]"), std::string::npos) << error_of(s, c);
  c = config(false);
  c.traversal_cost = -1.0;
  EXPECT_NE(error_of(s, c).find("costs must be finite and >= 0"), std::string::npos) << error_of(s, c);
  c = config(false);
  c.intersection_cost = std::nan("");
  EXPECT_NE(error_of(s, c).find("costs must be finite and >= 0"), std::string::npos) << error_of(s, c);
  for (const double bonus : {-0.1, 1.0}) {
    c = config(false);
    c.empty_bonus = bonus;
    EXPECT_NE(error_of(s, c).find("empty bonus"), std::string::npos) << error_of(s, c);
  }
  c = config(false);
  c.margin_ulps = -1;
  EXPECT_EQ(error_of(s, c), "kd-tree margin of -1 ulps is outside [0, 1024]; choose a margin in that range");
  c = config(false, fp::Format{9, 23});
  EXPECT_EQ(error_of(s, c), "kd-tree number format E9M23 is not one the units compute in; choose a format with "
                            "2 <= E <= 8 and 1 <= M <= 23 (docs/numbers.md)");
  Scene empty;
  empty.source = "nothing.json";
  EXPECT_EQ(error_of(empty, config(false)),
            "scene 'nothing.json' has no triangles to build a kd-tree over; add geometry");
}

TEST(KdTree, ConfigForNamesTheStackDepth) {
  for (const spec::HardwareConfig& h : spec::kConfigs) {
    const KdBuildConfig c = kd_build_config_for(std::string(h.name));
    EXPECT_EQ(c.max_depth, h.stack_depth);
    EXPECT_EQ(c.stack_depth, h.stack_depth);
    EXPECT_EQ(c.hardware_config, h.name);
  }
  try {
    kd_build_config_for("huge");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown hardware configuration 'huge' (spec/configs.toml has tiny, default, rpu2005, drpu)");
  }
}

TEST(KdTree, BuildIsDeterministic) {
  const Scene s = random_soup(2000, true, 9);
  const KdTree a = build_kdtree(s, config(true)), b = build_kdtree(s, config(true));
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].word0, b.nodes[i].word0);
    EXPECT_EQ(a.nodes[i].word1, b.nodes[i].word1);
  }
  EXPECT_EQ(a.prim_refs, b.prim_refs);
}

// Perfect splits give each straddling triangle its exact extent inside the child, so
// the SAH sees fewer false overlaps: never a worse tree on the sphereflake.
TEST(KdTree, PerfectSplitsDoNotRaiseTheSahCost) {
  const Scene s = make_sphereflake(2);
  const KdTree loose = build_kdtree(s, config(false)), perfect = build_kdtree(s, config(true));
  std::cout << "sphereflake balls:2, " << s.triangles.size() << " triangles\n"
            << "bounding-box splits:\n" << format_kd_stats(loose.stats)
            << "perfect splits:\n" << format_kd_stats(perfect.stats);
  EXPECT_LE(perfect.stats.sah_cost, loose.stats.sah_cost);
}

TEST(KdTree, StatsFormatNamesEveryField) {
  const KdTree tree = build_kdtree(make_cornell_box(), config(false));
  const std::string text = format_kd_stats(tree.stats);
  for (const char* word : {"nodes", "inner", "leaves", "empty", "depth", "prims per leaf", "prim refs",
                           "SAH cost", "bytes", "build time"}) {
    EXPECT_NE(text.find(word), std::string::npos) << word << " missing from:\n" << text;
  }
  EXPECT_NE(text.find("kd space         world x 2^-4\n"), std::string::npos) << text;  // 559 -> 35
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace rpu
