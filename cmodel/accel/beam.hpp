#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "accel/ray.hpp"
#include "accel/triangles.hpp"

namespace rpu::accel {

class Bvh;

// Beam tracing of primary rays (docs/accel.md, "Beams"): the rays of a tile of pixels
// go down the BVH together. Their common frustum (the planes through the shared origin
// and each two neighbouring corner rays) is tested against a node's box, or a leaf
// triangle's vertices, once for the whole beam; what lies beyond one plane is dropped for
// every ray of the beam. Everywhere else each ray decides for itself, as it would alone,
// so every ray gets exactly the hit it gets alone (its closest hit is a point of the ray,
// inside every box around its triangle, never beyond a frustum plane).

// The planes of a beam, each kept with the angle by which rounding lets a ray of the
// beam stray outside it.
class Frustum {
 public:
  // The frustum of `rays` whose corner rays are rays[corners[k]], in order around the
  // beam. Rays that do not share one origin, or corners that span no plane, give fewer
  // planes (none: nothing is ever culled).
  Frustum(std::span<const Ray> rays, const std::array<std::size_t, 4>& corners);

  // Whether no ray of the beam can meet the box [lo, hi]: its eight corners all lie
  // beyond one plane by more than the plane's margin.
  bool misses_box(const glm::dvec3& lo, const glm::dvec3& hi) const;
  // The same for the triangle's three vertices (a triangle lies in their convex hull).
  bool misses_triangle(const Triangle& tri) const;
  int planes() const { return planes_; }

 private:
  template <std::size_t N>
  bool beyond_a_plane(const std::array<glm::dvec3, N>& points) const;

  glm::dvec3 origin_{0.0};
  std::array<glm::dvec3, 4> normals_{};  // unit, pointing into the beam
  std::array<double, 4> margins_{};      // cosine margins of the angle outside the plane
  int planes_ = 0;
};

// What a beam's walk cost. ray_nodes: node boxes tested by individual rays (each ray's
// own slab test, where the frustum did not cull the node); ray_tests: ray/triangle tests;
// frustum_nodes, frustum_triangles: the beam's frustum tests. bytes: a node record or a
// triangle record is read once for the whole beam, at its frustum test (32 and 36 bytes,
// the BVH's byte model); the rays then use what the beam read.
struct BeamCost {
  std::uint64_t ray_nodes = 0, ray_tests = 0, frustum_nodes = 0, frustum_triangles = 0, bytes = 0;
};

// At most this many rays in one beam (a bit mask of the active rays).
inline constexpr int kMaxBeamRays = 64;

// The closest hits of the primary rays of a width x height image (row by row, as
// primary_rays makes them), traced in beams of beam x beam pixels (1..8; smaller at the
// image's right and bottom edges) through `bvh`.
std::vector<Hit> trace_primary_beams(const Bvh& bvh, std::span<const Ray> rays, int width, int height, int beam,
                                     BeamCost& cost);

}  // namespace rpu::accel
