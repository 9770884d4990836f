#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/ray.hpp"
#include "scene/geometry.hpp"
#include "scene/scene.hpp"

namespace rpu::accel {

// Bytes a structure reads per primitive test: the triangle's three fp32 vertices, the
// record a chip would fetch (the scene's vertices are fp32; the test widens them).
inline constexpr std::uint64_t kTriangleRecordBytes = 36;
// Bytes of one primitive reference (a 32-bit triangle index) in a cell or leaf list.
inline constexpr std::uint64_t kReferenceBytes = 4;

// Bytes of a structure stored as `nodes` records of `node_bytes` each, a list of
// `references` 32-bit triangle indices and `triangles` triangle records (docs/accel.md,
// "Byte model").
inline std::uint64_t stored_bytes(std::uint64_t nodes, std::uint64_t node_bytes, std::uint64_t references,
                                  std::uint64_t triangles) {
  return nodes * node_bytes + references * kReferenceBytes + triangles * kTriangleRecordBytes;
}

// A triangle ready for the ray test: a vertex and the two edges from it, in double.
struct Triangle {
  glm::dvec3 v0, e1, e2;
  std::uint32_t prim;  // index in Scene::triangles
};

// The one ray/triangle test of every structure (Moeller and Trumbore 1997) in double
// precision, so that all structures find bit-identical t for the same triangle and ray.
// Returns whether the ray meets the triangle (edges included) at a t in (t_min, t_max),
// and that t. det == 0 (the ray parallel to the plane) is a miss, never a division.
inline bool intersect(const Ray& ray, const Triangle& tri, double& t) {
  const glm::dvec3 p = glm::cross(ray.direction, tri.e2);
  const double det = glm::dot(tri.e1, p);
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const glm::dvec3 s = ray.origin - tri.v0;
  const double u = glm::dot(s, p) * inv;
  if (!(u >= 0.0 && u <= 1.0)) return false;
  const glm::dvec3 q = glm::cross(s, tri.e1);
  const double v = glm::dot(ray.direction, q) * inv;
  if (!(v >= 0.0 && u + v <= 1.0)) return false;
  t = glm::dot(tri.e2, q) * inv;
  return t > ray.t_min && t < ray.t_max;
}

// The triangles every structure is built over: the scene's, less those no structure can
// hit consistently (a vertex index out of range, a non-finite vertex, a degenerate
// triangle by scene/geometry.hpp's rule). The scene loader already drops degenerate
// ones; a Scene built in code may still hold them.
class TriangleSet {
 public:
  explicit TriangleSet(const Scene& scene);

  const std::vector<Triangle>& triangles() const { return triangles_; }
  std::size_t size() const { return triangles_.size(); }
  std::size_t skipped() const { return skipped_; }
  // Box around the kept triangles (empty when none are kept).
  const Bounds& bounds() const { return bounds_; }

 private:
  std::vector<Triangle> triangles_;  // in increasing prim order
  std::size_t skipped_ = 0;
  Bounds bounds_;
};

}  // namespace rpu::accel
