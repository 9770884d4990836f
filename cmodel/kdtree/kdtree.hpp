#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "fp/format.hpp"
#include "kdtree/kd_node.hpp"
#include "rpu/spec.hpp"
#include "scene/scene.hpp"

namespace rpu {

// How the SAH kd-tree is built (Wald & Havran 2006, "On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)"). Cost of a split:
//   traversal_cost + (1 - empty_bonus if a side is empty) *
//   intersection_cost * (P_below * N_below + P_above * N_above)
// with P the surface-area ratio of child to parent.
struct KdBuildConfig {
  // Defaults tuned on the built-in scenes and meshes (docs/kdtree.md, "Tuning"):
  // K_T = K_I costs rays within 1% of W&H's 15 : 20 and needs about a fifth less memory.
  double traversal_cost = 20.0;     // K_T
  double intersection_cost = 20.0;  // K_I
  double empty_bonus = 0.2;         // lambda: favours cutting off empty space
  std::uint32_t max_leaf_prims = 2; // stop splitting at this many primitives or fewer
  int max_depth = 32;               // tree depth limit (root = depth 0)
  int stack_depth = 32;             // the traversal unit's per-ray stack (hardware config)
  bool perfect_splits = true;       // clip triangles to the node box for split candidates
  // The number format the traversal and intersection units compute in (the hardware
  // config's `format`). Split values are exact in it, and triangles are classified by
  // their vertices rounded into it, widened by `margin_ulps` ulps of the format at the
  // scene's largest coordinate (docs/kdtree.md, "Conservative splits in any format").
  fp::Format format = fp::kFp32;
  int margin_ulps = 4;
  std::string hardware_config = "default";  // where stack_depth came from, for messages
};

// The deepest tree the builder accepts whatever the stack: it recurses once per level,
// and 64 levels already exceed any traversal stack a configuration would afford.
inline constexpr int kKdMaxDepthLimit = 64;

// The largest margin the builder accepts, in ulps of the format: far more than the
// units' rounding needs (docs/kdtree.md, "The margin"); more only inflates the tree.
inline constexpr int kKdMaxMarginUlps = 1024;

// The builder's defaults, with max_depth set to the stack depth and format to the number
// format of the named hardware configuration (spec/configs.toml). Throws rpu::Error for
// an unknown name.
KdBuildConfig kd_build_config_for(const std::string& hardware_config);
// The same for a resolved configuration (rpu::config::resolve).
KdBuildConfig kd_build_config_for(const spec::HardwareConfig& hardware_config);

struct KdTreeStats {
  std::uint64_t nodes = 0;
  std::uint64_t leaves = 0;
  std::uint64_t empty_leaves = 0;
  int max_depth = 0;
  double mean_leaf_depth = 0.0;
  double mean_prims_per_leaf = 0.0;  // over non-empty leaves
  std::uint64_t prim_refs = 0;
  double sah_cost = 0.0;             // expected cost of a random ray hitting the root box
  std::uint64_t bytes = 0;           // nodes + primitive-reference list
  int scale_exponent = 0;            // kd space = world x 2^-scale_exponent (KdTree)
  double build_seconds = 0.0;
};

// Kd space: the scene's coordinates times 2^-s, with s chosen so that the largest
// vertex coordinate magnitude lies in [2^m, 2^(m+1)) whatever the scene's scale, where
// m = min(kKdMagnitudeExponent, emax / 2) for the tree's number format (products of
// two coordinates stay finite in the narrowest formats). The tree, the intersection
// records and the root box are in kd space; the traversal unit moves each ray there and
// its hit distance back (docs/kdtree.md, "Kd space"; docs/traversal.md §1). Scaling by a power of two is
// exact in fp32 (fp::scale_fp32), so a scene scaled by 2^k has the same kd space, and
// its rays give the same hits.
//
// 2^5: the units form products of two ray-relative coordinates (watertight edge
// functions) and of a coordinate and an inverse edge length (Woop); the ranges of scale
// over which each format kept its primitive ids on the SPD sphereflake are centred near
// 2^5.6 (watertight) and 2^7.6 (Woop), and fp16's Woop range ends at 2^6.6
// (docs/traversal.md, "Limits of the formats").
inline constexpr int kKdMagnitudeExponent = 5;
// s lies within the exponents of normal fp32 numbers, so that 2^s and 2^-s are fp32
// powers of two and the ray unit holds s in 8 bits; the builder clamps to the lower end
// (scenes whose largest magnitude is below 2^-121 get a smaller kd space), the image
// validator rejects anything outside.
inline constexpr int kKdMinScaleExponent = -126;
inline constexpr int kKdMaxScaleExponent = 127;
int kd_scale_exponent(const Scene& scene, fp::Format format);
// The largest finite coordinate magnitude of a vertex a triangle uses (0 for none).
float largest_coordinate(const Scene& scene);
inline glm::vec3 to_kd_space(const glm::vec3& world, int scale_exponent) {
  glm::vec3 kd;
  for (int k = 0; k < 3; ++k) {
    kd[k] = std::bit_cast<float>(fp::scale_fp32(std::bit_cast<std::uint32_t>(world[k]), -scale_exponent));
  }
  return kd;
}

// A built tree, already in memory-image form: nodes[0] is the root, depth-first with
// the below child right after its parent; prim_refs holds the leaves' triangle indices.
// Split values and the root box are in kd space.
struct KdTree {
  std::vector<KdNode> nodes;
  std::vector<std::uint32_t> prim_refs;
  glm::vec3 bounds_lo{0.0f}, bounds_hi{0.0f};  // the root box (the scene's bounds in kd space)
  int scale_exponent = 0;                      // s of kd space = world x 2^-s
  fp::Format format = fp::kFp32;               // the format it was built for (config.format)
  KdTreeStats stats;
};

// Builds the tree over scene.triangles in kd space in O(N log N). Throws rpu::Error
// when the configuration is impossible: max_depth > stack_depth (traversal pushes at
// most one entry per level, so a deeper tree could overflow the unit's stack), negative
// costs, max_depth < 0 or above kKdMaxDepthLimit, empty_bonus outside [0, 1), a scene
// without triangles, a format or margin out of range (a margin beyond the format's
// range), or a tree whose node or reference count overflows the node's index bits.
// Every split value and the root box are exact, normal (or zero) values of
// config.format. Every leaf references each triangle whose kd-space vertices rounded
// into config.format span a triangle that comes within the margin of its closed box
// (without perfect_splits: whose bounding box does), so a point on a split plane finds
// its triangle on both sides.
KdTree build_kdtree(const Scene& scene, const KdBuildConfig& config);

// The statistics as a few aligned lines for `rpu tree`, each ending in a newline.
std::string format_kd_stats(const KdTreeStats& stats);

// Where a format cannot place the planes a scene needs: its planes lie on the format's
// grid and every triangle is widened by the format's rounding margin, so when both are
// coarser than the scene's triangles the SAH finds few splits worth making. The tree
// of the format, against the fp32 tree of the same scene, is said to have lost planes
// when its SAH cost is more than kLostPlanesRatio times fp32's; then a note for the
// user, naming the format and both trees (nothing otherwise).
inline constexpr double kLostPlanesRatio = 1.5;
std::string lost_planes_note(const std::string& format_name, const KdTreeStats& tree, const KdTreeStats& fp32_tree);

}  // namespace rpu
