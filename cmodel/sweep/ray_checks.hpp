#pragma once

#include <cstdint>
#include <vector>

#include "kdtree/kdtree.hpp"
#include "memory/memory_image.hpp"
#include "scene/scene.hpp"

// What a sweep point measures of the trace units beside the image (docs/sweeps.md,
// "What a point measures"): the golden traversal and intersection units in the point's
// number format and intersection test against a double-precision trace of the same rays.
namespace rpu::sweep {

struct RayChecks {
  // Primary rays through the pixel centres, traced by the units and by the reference
  // renderer's fp64 BVH; a mismatch is a ray where one hits and the other misses, or
  // both hit different triangles.
  std::uint64_t primary_rays = 0;
  std::uint64_t hit_mismatches = 0;
  // Rays from a point inside each closed mesh of the scene (every edge shared by exactly
  // two triangles) to a point of one of its edges or a vertex, traced against that mesh
  // alone: every one must hit it, and a leak is one that gets out.
  std::uint64_t closed_meshes = 0;  // the closed meshes an inside point was found for
  std::uint64_t leak_rays = 0;
  std::uint64_t leaks = 0;
  // The extremes (docs/sweeps.md, "Extremes"), each against the fp64 trace of the same
  // ray as above: rays exactly parallel to an axis through a triangle's centroid; grazing
  // rays, 1e-3 radians off a triangle's plane, through its centroid; rays from a point
  // exactly on a triangle (as close as float gets) leaving it, t_min 0.
  std::uint64_t axis_rays = 0, axis_mismatches = 0;
  std::uint64_t grazing_rays = 0, grazing_mismatches = 0;
  std::uint64_t surface_rays = 0, surface_mismatches = 0;
};

// `hit_check`: trace width x height primary rays; `leak_rays`: that many rays, shared
// among the closed meshes; `extreme_rays`: that many of each extreme kind. Deterministic
// for a seed.
RayChecks check_rays(const Scene& world, const KdBuildConfig& build, IsectMode mode, int width, int height,
                     bool hit_check, std::uint32_t leak_rays, std::uint64_t seed, std::uint32_t extreme_rays = 0);

// The scene's closed meshes: the connected sets of triangles (joined at shared edges,
// vertices welded by position) in which every edge belongs to exactly two triangles,
// each as a scene of its own (the world's camera, lights and materials).
std::vector<Scene> closed_meshes(const Scene& world);

}  // namespace rpu::sweep
