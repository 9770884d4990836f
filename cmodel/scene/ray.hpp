#pragma once

#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace rpu {

// A ray in double precision; a hit counts only for t in the open interval (t_min, t_max).
// The direction need not be unit length: t is in units of it. The reference renderer,
// the acceleration structures of rpu accel and the fp64 checks of a sweep trace these.
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
  double t_min = 0.0;
  double t_max = std::numeric_limits<double>::infinity();
};

inline constexpr std::uint32_t kNoPrimitive = std::numeric_limits<std::uint32_t>::max();

// A ray's hit: its distance, the triangle (its index in Scene::triangles) and the
// barycentrics of the triangle's second and third vertices, where the test computes
// them. As the closest hit of the acceleration structures: the smallest t, and of equal
// t the smallest triangle, so every structure names the same triangle whatever order it
// tests them in (improved_by).
struct Hit {
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t prim = kNoPrimitive;
  double u = 0.0, v = 0.0;

  bool hit() const { return prim != kNoPrimitive; }
  // Whether a hit at (t, prim) would replace this one.
  bool improved_by(double other_t, std::uint32_t other_prim) const {
    return other_t < t || (other_t == t && other_prim < prim);
  }
};

}  // namespace rpu
