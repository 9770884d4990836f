// The numbers in docs/kdtree.md: tree statistics of scenes (one Markdown row each) and,
// with --rays, what a ray costs in each tree: inner nodes visited and triangles tested
// per ray, counted by a plain double-precision front-to-back traversal (not the
// hardware's) of rays from random points in the scene box to random points on random
// triangles. The costs the builder should use are the ones that minimise
// K_T * nodes/ray + K_I * tests/ray for the hardware's real K_T : K_I at moderate memory.
//
//   build/ci/bench/kdtree/kdtree_table [--rays] [--kt 15] [--ki 20] [--bonus 0.2]
//       [--leaf 2] [--perfect 0|1] [--format fp32|e8m15|rpu24|bf16|fp16] [--margin 4] [--hash] [--json] SCENE...
//
// --hash adds a column with an FNV-1a hash of the nodes and the reference list, so that
// a change meant to speed the builder up can show it builds the identical tree. --json
// prints one JSON object per scene instead of the Markdown rows, with every number at
// full precision (scripts/bench-record kdtree-stats reads it).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"
#include "common/random_vector.hpp"

namespace rpu {
namespace {

// Möller-Trumbore in double; only the hit distance matters here.
bool intersect(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
               const glm::dvec3& c, double& t) {
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0) return false;
  const glm::dvec3 s = o - a, q = glm::cross(s, e1);
  const double u = glm::dot(s, p) / det, v = glm::dot(d, q) / det;
  if (u < 0.0 || v < 0.0 || u + v > 1.0) return false;
  t = glm::dot(e2, q) / det;
  return t > 0.0;
}

struct RayCost {
  double steps = 0.0, tests = 0.0;
};

RayCost measure_rays(const Scene& scene, const KdTree& tree, int rays) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const glm::dvec3 lo(tree.bounds_lo), hi(tree.bounds_hi);
  // The tree's box is in kd space (world x 2^-scale_exponent, exact), so the rays are too.
  const auto vertex = [&](std::uint32_t t, int k) {
    return glm::dvec3(to_kd_space(scene.positions[scene.triangles[t][k]], tree.scale_exponent));
  };
  std::uint64_t steps = 0, tests = 0;
  struct Item {
    std::uint32_t node;
    double t0, t1;
  };
  std::vector<Item> stack;
  for (int r = 0; r < rays; ++r) {
    const glm::dvec3 o = lo + (hi - lo) * random_vector(u, rng);
    const auto tri = static_cast<std::uint32_t>(u(rng) * static_cast<double>(scene.triangles.size()));
    double s = u(rng), w = u(rng);
    if (s + w > 1.0) {
      s = 1.0 - s;
      w = 1.0 - w;
    }
    const glm::dvec3 a = vertex(tri, 0), target = a + s * (vertex(tri, 1) - a) + w * (vertex(tri, 2) - a);
    const glm::dvec3 d = glm::normalize(target - o);
    double t0 = 0.0, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
      double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    double nearest = INFINITY;
    stack.assign(1, {0, t0, t1});
    while (!stack.empty()) {
      Item it = stack.back();
      stack.pop_back();
      if (it.t0 > nearest) continue;
      std::uint32_t node = it.node;
      for (;;) {
        const KdNode n = tree.nodes[node];
        if (n.is_leaf()) {
          for (std::uint32_t i = 0; i < n.prim_count(); ++i) {
            const std::uint32_t t = tree.prim_refs[n.first_prim_ref() + i];
            double th = 0.0;
            ++tests;
            if (intersect(o, d, vertex(t, 0), vertex(t, 1), vertex(t, 2), th)) nearest = std::min(nearest, th);
          }
          break;
        }
        ++steps;
        const int k = n.split_axis();
        const double split = n.split(), ts = (split - o[k]) / d[k];
        const bool below_first = o[k] < split || (o[k] == split && d[k] <= 0.0);
        const std::uint32_t first = below_first ? node + 1 : n.above_child();
        const std::uint32_t second = below_first ? n.above_child() : node + 1;
        if (ts > it.t1 || ts <= 0.0) {
          node = first;
        } else if (ts < it.t0) {
          node = second;
        } else {
          stack.push_back({second, ts, it.t1});
          it.t1 = ts;
          node = first;
        }
      }
      if (nearest <= it.t1) break;
    }
  }
  return {static_cast<double>(steps) / rays, static_cast<double>(tests) / rays};
}

// FNV-1a over every node word and reference, in order.
std::uint64_t tree_hash(const KdTree& tree) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  const auto mix = [&h](std::uint32_t word) {
    for (int byte = 0; byte < 4; ++byte) h = (h ^ ((word >> (8 * byte)) & 0xffu)) * 0x100000001b3ull;
  };
  for (const KdNode& n : tree.nodes) {
    mix(n.word0);
    mix(n.word1);
  }
  for (const std::uint32_t r : tree.prim_refs) mix(r);
  return h;
}

int run(int argc, char** argv) {
  KdBuildConfig config = kd_build_config_for("default");
  bool rays = false, hash = false, json = false;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&] { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (arg == "--rays") rays = true;
    else if (arg == "--hash") hash = true;
    else if (arg == "--json") json = true;
    else if (arg == "--kt") config.traversal_cost = value();
    else if (arg == "--ki") config.intersection_cost = value();
    else if (arg == "--bonus") config.empty_bonus = value();
    else if (arg == "--leaf") config.max_leaf_prims = static_cast<std::uint32_t>(value());
    else if (arg == "--perfect") config.perfect_splits = value() != 0.0;
    else if (arg == "--margin") config.margin_ulps = static_cast<int>(value());
    else if (arg == "--format" && i + 1 < argc) config.format = fp::format_by_name(argv[++i]);
    else scenes.push_back(arg);
  }
  if (!json) {
    std::printf("| scene | triangles | nodes | leaves | empty | max/mean depth | prims/leaf | refs/tri | SAH cost | "
                "bytes | build s |%s\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|%s\n",
                (std::string(rays ? " nodes/ray | tests/ray |" : "") + (hash ? " hash |" : "")).c_str(),
                (std::string(rays ? "--:|--:|" : "") + (hash ? "---|" : "")).c_str());
  }
  for (const std::string& name : scenes) {
    const Scene scene = resolve_scene(name);
    const KdTree tree = build_kdtree(scene, config);
    const KdTreeStats& s = tree.stats;
    const double tris = static_cast<double>(scene.triangles.size());
    if (json) {
      nlohmann::json row = {{"scene", name},
                            {"triangles", scene.triangles.size()},
                            {"nodes", s.nodes},
                            {"leaves", s.leaves},
                            {"empty", s.empty_leaves},
                            {"max_depth", s.max_depth},
                            {"mean_depth", s.mean_leaf_depth},
                            {"prims_per_leaf", s.mean_prims_per_leaf},
                            {"refs_per_tri", static_cast<double>(s.prim_refs) / tris},
                            {"sah", s.sah_cost},
                            {"bytes", s.bytes},
                            {"build_s", s.build_seconds},
                            {"config", {{"format", config.format.name()},
                                        {"margin_ulps", config.margin_ulps},
                                        {"kt", config.traversal_cost},
                                        {"ki", config.intersection_cost},
                                        {"lambda", config.empty_bonus},
                                        {"max_leaf_prims", config.max_leaf_prims},
                                        {"perfect_splits", config.perfect_splits},
                                        {"max_depth", config.max_depth}}}};
      if (rays) {
        const RayCost c = measure_rays(scene, tree, 100000);
        row["nodes_per_ray"] = c.steps;
        row["tests_per_ray"] = c.tests;
      }
      if (hash) {
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(tree_hash(tree)));
        row["hash"] = hex;
      }
      std::printf("%s\n", row.dump().c_str());
      continue;
    }
    std::printf("| %s | %zu | %llu | %llu | %llu | %d / %.1f | %.2f | %.2f | %.1f | %llu | %.3f |", name.c_str(),
                scene.triangles.size(), static_cast<unsigned long long>(s.nodes),
                static_cast<unsigned long long>(s.leaves), static_cast<unsigned long long>(s.empty_leaves),
                s.max_depth, s.mean_leaf_depth, s.mean_prims_per_leaf, static_cast<double>(s.prim_refs) / tris,
                s.sah_cost, static_cast<unsigned long long>(s.bytes), s.build_seconds);
    if (rays) {
      const RayCost c = measure_rays(scene, tree, 100000);
      std::printf(" %.1f | %.1f |", c.steps, c.tests);
    }
    if (hash) std::printf(" %016llx |", static_cast<unsigned long long>(tree_hash(tree)));
    std::printf("\n");
  }
  return 0;
}

}  // namespace
}  // namespace rpu

int main(int argc, char** argv) {
  try {
    return rpu::run(argc, argv);
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "kdtree_table: error: %s\n", e.what());
    return 1;
  }
}
