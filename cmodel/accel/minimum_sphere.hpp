#pragma once

#include <span>

#include <glm/glm.hpp>

#include "accel/bounding_volumes.hpp"

namespace rpu::accel {

// The smallest sphere around the points, by CGAL's Min_sphere_of_spheres_d (Fischer and
// Gaertner 2003) in double precision: the optimum Ritter's sphere is measured against.
// No points: radius 0 at the origin.
Sphere minimum_sphere(std::span<const glm::dvec3> points);

}  // namespace rpu::accel
