#pragma once

#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace rpu::accel {

// A ray in double precision; a hit counts only for t in the open interval (t_min, t_max).
// The direction need not be unit length: t is in units of it.
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
  double t_min = 0.0;
  double t_max = std::numeric_limits<double>::infinity();
};

inline constexpr std::uint32_t kNoPrimitive = std::numeric_limits<std::uint32_t>::max();

// The closest hit: the smallest t, and of equal t the smallest primitive id (the index of
// the triangle in Scene::triangles), so every structure names the same triangle whatever
// order it tests them in.
struct Hit {
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t prim = kNoPrimitive;

  bool hit() const { return prim != kNoPrimitive; }
  // Whether a hit at (t, prim) would replace this one.
  bool improved_by(double other_t, std::uint32_t other_prim) const {
    return other_t < t || (other_t == t && other_prim < prim);
  }
};

// What one ray cost a structure. nodes: nodes (grid cells) whose record was read;
// tests: ray/triangle tests; bytes: every byte read from the structure's memory, by the
// byte model each structure states (docs/accel.md, "Byte model").
struct RayCost {
  std::uint64_t nodes = 0;
  std::uint64_t tests = 0;
  std::uint64_t bytes = 0;

  RayCost& operator+=(const RayCost& o) {
    nodes += o.nodes;
    tests += o.tests;
    bytes += o.bytes;
    return *this;
  }
};

}  // namespace rpu::accel
