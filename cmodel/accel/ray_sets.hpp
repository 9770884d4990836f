#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "accel/ray.hpp"
#include "accel/triangles.hpp"
#include "scene/scene.hpp"

namespace rpu::accel {

// The rays the structures are compared on.

// One ray through the centre of each pixel of a width x height image from the scene's
// camera (render/sampling.hpp's CameraModel, lens centre), row by row from the top.
std::vector<Ray> primary_rays(const Scene& scene, int width, int height);

// Rays from a random point towards another of the triangles' box grown by a tenth of
// its size on each side (unit direction, unbounded t). Points are drawn with
// rpu::random_vector from std::mt19937(seed).
std::vector<Ray> random_rays(const TriangleSet& triangles, int count, std::uint32_t seed);

// From each hit of `rays` (hits[i] is rays[i]'s closest hit), a ray to each light the
// hit faces (its geometric normal turned towards the ray's origin): to a point light,
// to a random point of an area light, or against a directional light's direction. The
// origin is lifted off the surface by 1e-4 of the scene's diagonal along the normal and
// t ends that far before the light (as the reference renderer does); unit direction.
std::vector<Ray> shadow_rays(const Scene& scene, const TriangleSet& triangles, std::span<const Ray> rays,
                             std::span<const Hit> hits, std::uint32_t seed);

}  // namespace rpu::accel
