#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/structure.hpp"

namespace rpu::accel {

// An axis-aligned BSP tree of midpoint splits with the axes in turn, x, y, z, x, ...
// (the lecture's Subdivide: Kaplan 1985; Sung and Shirley 1992, "Ray tracing with the
// BSP tree"): a node's box is halved across axis depth mod 3 until it holds at most
// kMaxLeafTriangles triangles or lies kMaxDepth levels down, three levels for each of
// the octree's (so both stop at boxes of the same size). A triangle goes into each half
// the separating-axis test finds it overlapping (padded as box.hpp says). The root is the
// scene's box. Traversal: RayTreeIntersect (split_plane_walk.hpp).
//
// Storage and byte model: the kd-tree's 8-byte node (axis or leaf, the above child's
// index or the leaf's count, the fp32 plane or the leaf's first reference; the below
// child follows its parent), 4 bytes a reference, 36 bytes a triangle record.
class Bsp final : public Structure {
 public:
  static constexpr int kMaxDepth = 30;
  static constexpr std::uint32_t kMaxLeafTriangles = 8;
  static constexpr std::uint64_t kNodeBytes = 8;

  explicit Bsp(const TriangleSet& triangles);

  std::string_view name() const override { return "bsp"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override {
    return stored_bytes(nodes_.size(), kNodeBytes, references_.size(), triangles_.size());
  }
  std::uint64_t node_count() const override { return nodes_.size(); }
  int depth() const { return depth_; }

 private:
  struct Node {
    std::uint32_t index;  // inner: the above child (the below child is the next node); leaf: first reference
    std::uint32_t count;  // leaf: its references; inner: kInner
    int axis;             // inner
    double split;         // inner
  };
  static constexpr std::uint32_t kInner = ~std::uint32_t{0};

  std::uint32_t build(const glm::dvec3& lo, const glm::dvec3& hi, int depth, const std::vector<std::uint32_t>& items);
  template <bool kAnyHit>
  Hit traverse(const Ray& ray, RayCost& cost) const;

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;                // depth first; the root is node 0
  std::vector<std::uint32_t> references_;  // indices into triangles_, ascending within a leaf
  glm::dvec3 lo_{0.0}, hi_{0.0};           // the root box, padded
  double pad_ = 0.0;
  int depth_ = 0;
};

}  // namespace rpu::accel
