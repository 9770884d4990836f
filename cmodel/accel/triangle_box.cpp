#include "accel/triangle_box.hpp"

#include <algorithm>
#include <cmath>

namespace rpu::accel {

namespace {
// Whether `axis` separates the triangle's vertices (box-centred) from a box of half size h.
bool separates(const glm::dvec3& axis, const glm::dvec3 (&v)[3], const glm::dvec3& h) {
  const double p0 = glm::dot(axis, v[0]), p1 = glm::dot(axis, v[1]), p2 = glm::dot(axis, v[2]);
  const double radius = glm::dot(h, glm::abs(axis));
  return std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius;
}
}  // namespace

bool triangle_overlaps_box(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& lo,
                           const glm::dvec3& hi) {
  const glm::dvec3 centre = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const glm::dvec3 v[3] = {a - centre, b - centre, c - centre};
  // The box's normals: the boxes of triangle and box overlap.
  for (int k = 0; k < 3; ++k) {
    if (std::min({v[0][k], v[1][k], v[2][k]}) > h[k] || std::max({v[0][k], v[1][k], v[2][k]}) < -h[k]) return false;
  }
  const glm::dvec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  // The triangle's normal: its plane passes through the box.
  if (separates(glm::cross(edges[0], edges[1]), v, h)) return false;
  // Each box normal times each edge. A zero product (an edge along a box axis) projects
  // everything to 0 and separates nothing.
  for (const glm::dvec3& e : edges) {
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 unit(0.0);
      unit[k] = 1.0;
      if (separates(glm::cross(unit, e), v, h)) return false;
    }
  }
  return true;
}

}  // namespace rpu::accel
