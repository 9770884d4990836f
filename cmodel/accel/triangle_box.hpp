#pragma once

#include <glm/glm.hpp>

namespace rpu::accel {

// Whether the triangle (a, b, c) and the closed box [lo, hi] share a point, by the
// separating-axis theorem over the 13 axes of Akenine-Moeller 2001: the box's three
// normals, the triangle's normal and the nine products of a box normal and a triangle
// edge. Touching counts as overlapping.
bool triangle_overlaps_box(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& lo,
                           const glm::dvec3& hi);

}  // namespace rpu::accel
