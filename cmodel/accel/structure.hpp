#pragma once

#include <cstdint>
#include <memory>
#include <span>
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

// The leaf loop every structure shares. One triangle test: counted with its record's
// bytes; a hit that improves `best` (Hit's tie rule) replaces it. Returns whether the ray
// met the triangle.
inline bool test_triangle(const Ray& ray, const Triangle& tri, Hit& best, RayCost& cost) {
  ++cost.tests;
  cost.bytes += kTriangleRecordBytes;
  double t;
  if (!intersect(ray, tri, t)) return false;
  if (best.improved_by(t, tri.prim)) best = {t, tri.prim};
  return true;
}

// Triangles stored in leaf order (the BVH, brute force): each tested. Returns true when an
// any-hit query (kAnyHit) has its answer and the walk can stop; `best` then holds the hit.
template <bool kAnyHit>
bool test_triangles(const Ray& ray, std::span<const Triangle> triangles, Hit& best, RayCost& cost) {
  for (const Triangle& tri : triangles) {
    if (test_triangle(ray, tri, best, cost) && kAnyHit) return true;
  }
  return false;
}

// A leaf's (a cell's) references into `triangles`: each reference read (kReferenceBytes),
// and its triangle tested when test_it(k) says so (the grid's mailboxes skip a triangle
// this ray has tested). Returns as test_triangles does.
template <bool kAnyHit, typename TestIt>
bool test_references(const Ray& ray, const std::vector<Triangle>& triangles,
                     std::span<const std::uint32_t> references, Hit& best, RayCost& cost, TestIt test_it) {
  for (const std::uint32_t k : references) {
    cost.bytes += kReferenceBytes;
    if (!test_it(k)) continue;
    if (test_triangle(ray, triangles[k], best, cost) && kAnyHit) return true;
  }
  return false;
}

template <bool kAnyHit>
bool test_references(const Ray& ray, const std::vector<Triangle>& triangles,
                     std::span<const std::uint32_t> references, Hit& best, RayCost& cost) {
  return test_references<kAnyHit>(ray, triangles, references, best, cost, [](std::uint32_t) { return true; });
}

// Build parameters of every structure; each takes the ones it knows.
struct StructureOptions {
  double grid_lambda = 4.0;  // grid cells per triangle (uniform_grid.hpp)
  bool grid_mailbox = true;  // test a triangle at most once per ray in the grid
};

// The structures build_structure knows, in table order: "brute", "grid", "octree",
// "octree-r", "bsp", "bvh", "kdtree".
std::vector<std::string> structure_names();
// Throws rpu::Error for a name structure_names() does not list, a bad option, or a scene
// the kd-tree builder refuses (coordinates beyond its format's range).
std::unique_ptr<Structure> build_structure(std::string_view name, const TriangleSet& triangles,
                                           const StructureOptions& options);

}  // namespace rpu::accel
