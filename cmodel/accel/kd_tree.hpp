#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/structure.hpp"
#include "kdtree/kdtree.hpp"

namespace rpu::accel {

// The project's SAH kd-tree, exactly as the memory image holds it for the traversal unit
// (cmodel/kdtree, docs/kdtree.md: Wald and Havran 2006, the `default` hardware
// configuration's build settings), walked here in double precision front to back with
// an explicit stack (pbrt-v3, KdTreeAccel::Intersect). As in the grid, a leaf's hit ends
// the walk only if it lies within the leaf's t-range; the builder's margin puts a
// triangle touching a split plane on both sides of it.
//
// Storage and byte model: a node is 8 bytes (docs/memory-map.md: axis or leaf, child
// index or count, split or first reference), a reference a 32-bit triangle index, and a
// test reads the triangle's 36-byte record (the 48-byte Woop records the intersection
// unit reads are not modelled here, so that all structures pay one record size).
class KdTreeStructure final : public Structure {
 public:
  static constexpr std::uint64_t kNodeBytes = sizeof(KdNode);

  explicit KdTreeStructure(const TriangleSet& triangles);

  std::string_view name() const override { return "kdtree"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override {
    return stored_bytes(tree_.nodes.size(), kNodeBytes, tree_.prim_refs.size(), triangles_.size());
  }
  std::uint64_t node_count() const override { return tree_.nodes.size(); }

 private:
  template <bool kAnyHit>
  Hit traverse(const Ray& ray, RayCost& cost) const;

  std::vector<Triangle> triangles_;  // the kept triangles; prim_refs index them
  KdTree tree_;
  std::vector<double> splits_;  // per node, its split in world space (2^s times kd space: exact)
  glm::dvec3 lo_{0.0}, hi_{0.0};  // the root box in world space, padded (box.hpp)
};

}  // namespace rpu::accel
