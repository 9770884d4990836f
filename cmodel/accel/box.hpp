#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include "accel/ray.hpp"
#include "scene/geometry.hpp"

namespace rpu::accel {

// Every box a structure stores (grid cells, BVH nodes) is its exact box grown by this
// fraction of the scene's diagonal on each side. The structures then answer exactly as
// brute force does although their box arithmetic and the triangle test round
// differently: a hit point near a box face (a wall of the Cornell box lies in the face
// of every box around it) stays inside the padded box as long as the triangle test's t
// is off by less than the pad: tests/accel holds it for rays skimming a triangle's plane
// at down to 1e-10 rad. The cost is a few extra references in cells the pad reaches.
inline constexpr double kBoxPadFraction = 1e-8;

inline double box_pad(const Bounds& scene) {
  return scene.empty() ? 0.0 : kBoxPadFraction * glm::length(scene.hi - scene.lo);
}

// 1/d per axis; a zero component gets a huge finite reciprocal of its sign instead of
// inf, so that an origin exactly on a slab plane gives 0 * big = 0, never 0 * inf = NaN.
inline glm::dvec3 safe_reciprocal(const glm::dvec3& d) {
  glm::dvec3 inv;
  for (int a = 0; a < 3; ++a) inv[a] = d[a] != 0.0 ? 1.0 / d[a] : std::copysign(1e300, d[a]);
  return inv;
}

// Narrows [t_near, t_far] to the ray's parameters inside the box (slab test, Kay and
// Kajiya 1986); false when nothing is left. The far end is widened by 2 gamma_3 of itself so
// that rounding never loses a box the ray touches (Ize 2013, "Robust BVH Ray Traversal").
inline bool clip_to_box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& origin,
                        const glm::dvec3& inv_dir, double& t_near, double& t_far) {
  constexpr double kEps = std::numeric_limits<double>::epsilon() / 2;
  constexpr double kFarWidening = 2.0 * (3.0 * kEps / (1.0 - 3.0 * kEps));
  for (int a = 0; a < 3; ++a) {
    double t0 = (lo[a] - origin[a]) * inv_dir[a];
    double t1 = (hi[a] - origin[a]) * inv_dir[a];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1 + std::abs(t1) * kFarWidening);
  }
  return t_near <= t_far;
}

// Where a ray enters a structure's root box [lo, hi] and leaves it (its t-range clipped
// to the box), with its reciprocal direction for the walk; `entered` false when it misses.
struct RootSegment {
  glm::dvec3 inv;
  double t_near, t_far;
  bool entered;
};

inline RootSegment enter_root(const glm::dvec3& lo, const glm::dvec3& hi, const Ray& ray) {
  RootSegment s{safe_reciprocal(ray.direction), ray.t_min, ray.t_max, false};
  s.entered = clip_to_box(lo, hi, ray.origin, s.inv, s.t_near, s.t_far);
  return s;
}

}  // namespace rpu::accel
