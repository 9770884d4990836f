#pragma once

#include <cstddef>
#include <limits>
#include <string>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace rpu {

// An axis-aligned box; empty (lo > hi) until a point is added. In double precision for
// the scene (Bounds), in fp32 for what the hardware's kd-tree holds (Bounds32).
template <class Vec>
struct BasicBounds {
  Vec lo{std::numeric_limits<typename Vec::value_type>::infinity()};
  Vec hi{-std::numeric_limits<typename Vec::value_type>::infinity()};

  bool empty() const { return lo.x > hi.x; }
  void extend(const Vec& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
};
using Bounds = BasicBounds<glm::dvec3>;
using Bounds32 = BasicBounds<glm::vec3>;

// The point of `light` that (s, t) in [0, 1)^2 picks: an area light's
// position + s edge_u + t edge_v, a point light's position whatever s and t. Callers
// draw s and t only for area lights, so a scene of point lights uses no random numbers.
glm::dvec3 light_sample_point(const Light& light, double s, double t);

// Box around every vertex some triangle uses (unreferenced vertices do not count).
Bounds scene_bounds(const Scene& scene);

// A triangle is degenerate when twice its area is at most this fraction of its
// longest edge squared, i.e. its smallest angle is below about 1e-6 rad: zero-area,
// needle and collinear triangles. Such triangles have no usable plane (the Woop
// transform is singular) and nothing to render; fp32 vertices resolve about 6e-8.
inline constexpr double kDegenerateRatio = 1e-6;
bool is_degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// Removes the degenerate triangles of `part` (and their material ids). When any were
// dropped, adds ONE warning "<name>: dropped N degenerate triangles (...)" to
// part.warnings. Returns how many were dropped.
std::size_t drop_degenerate_triangles(Scene& part, const std::string& name);

// Merges vertices whose position, normal and uv (where the part has them) are equal,
// +0 and -0 alike, and renumbers the triangles. Equality, not a distance: a tolerance
// would merge differently at each scale of the same mesh (Assimp's
// JoinIdenticalVertices welded distinct vertices of small meshes).
void weld_identical_vertices(Scene& part);

// Gives every vertex the normalised sum of the unit normals of the triangles that use
// its position (Assimp's GenSmoothNormals without its distance tolerance); (0, 0, 1)
// where they cancel. Replaces any normals the part had.
void generate_smooth_normals(Scene& part);

// Multiplies every length of the scene by 2^exponent: vertices, the camera's position,
// look-at point, aperture and focus distance, the lights' positions and edges. Exact in
// binary floating point while nothing overflows or turns subnormal, so the scaled scene
// renders the same image; directions, colours and materials do not change.
void scale_scene(Scene& scene, int exponent);

// Moves every position of the scene (vertices, camera, lights) by `offset`: the same
// picture, further from the origin (rpu render --translate; the extremes of
// docs/sweeps.md). Vertices are rounded to float where they land.
void translate_scene(Scene& scene, const glm::dvec3& offset);

// Appends the geometry and warnings of `part` to `scene`. part.material_ids already
// index scene.materials. Per-vertex normals and uvs are all or nothing over the whole
// scene: a side without normals gets flat (face) normals, which un-shares its
// vertices; a side without uvs gets (0, 0).
void append_geometry(Scene& scene, Scene&& part);

}  // namespace rpu
