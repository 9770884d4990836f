#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "accel/ray.hpp"
#include "accel/triangles.hpp"

namespace rpu::accel {

// One acceleration structure over a TriangleSet, built by its constructor (the caller
// times the build). Queries are single-threaded: a structure may keep per-ray scratch
// state (the grid's mailboxes). Every query adds what it read to `cost`.
class Structure {
 public:
  virtual ~Structure() = default;

  virtual std::string_view name() const = 0;
  // The parameters the build chose or was given ("40x40x40 cells, lambda 4"), for tables.
  virtual std::string parameters() const = 0;
  // The smallest t in (t_min, t_max), of equal t the smallest primitive id; no hit when
  // the ray meets no triangle there.
  virtual Hit closest_hit(const Ray& ray, RayCost& cost) const = 0;
  // Whether the ray meets some triangle at a t in (t_min, t_max).
  virtual bool any_hit(const Ray& ray, RayCost& cost) const = 0;
  // Bytes of the structure as a chip would store it: its nodes, reference lists and
  // triangle records (docs/accel.md, "Byte model"); traversal scratch is not included.
  virtual std::uint64_t memory_bytes() const = 0;
  // Nodes (for the grid, cells) the structure holds.
  virtual std::uint64_t node_count() const = 0;
};

// Build parameters of every structure; each takes the ones it knows.
struct StructureOptions {
  double grid_lambda = 4.0;  // grid cells per triangle (uniform_grid.hpp)
  bool grid_mailbox = true;  // test a triangle at most once per ray in the grid
};

// The structures build_structure knows, in table order: "brute", "grid", "octree", "bvh",
// "kdtree".
std::vector<std::string> structure_names();
// Throws rpu::Error for a name structure_names() does not list, a bad option, or a scene
// the kd-tree builder refuses (coordinates beyond its format's range).
std::unique_ptr<Structure> build_structure(std::string_view name, const TriangleSet& triangles,
                                           const StructureOptions& options);

}  // namespace rpu::accel
