#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/structure.hpp"

namespace rpu::accel {

// An octree: the scene's box made a cube and split into eight equal octants until a node
// holds at most kMaxLeafTriangles triangles or lies kMaxDepth levels down (the two
// termination rules of the classic octree; Glassner 1984). A triangle goes into each
// octant the separating-axis test finds it overlapping (padded as box.hpp says).
// Traversal is front to back with an explicit stack: a node's segment of the ray is cut
// at its three mid-planes into the (at most four) octants it crosses, in order; as in the
// grid, a leaf's hit ends the walk only if it lies within the leaf's t-range.
//
// Storage and byte model: a node is 8 bytes (an inner node: the index of its first
// child, the eight children stored together; a leaf: its first reference and count);
// the octants' boxes follow from the root cube, so no bounds are stored. A reference is
// a 32-bit triangle index (4 bytes); a test reads the 36-byte triangle record.
class Octree final : public Structure {
 public:
  static constexpr int kMaxDepth = 10;
  static constexpr std::uint32_t kMaxLeafTriangles = 8;
  static constexpr std::uint64_t kNodeBytes = 8;

  explicit Octree(const TriangleSet& triangles);

  std::string_view name() const override { return "octree"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override {
    return nodes_.size() * kNodeBytes + references_.size() * kReferenceBytes +
           triangles_.size() * kTriangleRecordBytes;
  }
  std::uint64_t node_count() const override { return nodes_.size(); }
  int depth() const { return depth_; }

 private:
  struct Node {
    std::uint32_t first;  // inner: the first of its eight children; leaf: its first reference
    std::uint32_t count;  // leaf: its references; inner: kInner
  };
  static constexpr std::uint32_t kInner = ~std::uint32_t{0};

  void build(std::uint32_t index, const glm::dvec3& lo, double size, int depth, std::vector<std::uint32_t>& items);
  template <bool kAnyHit>
  Hit traverse(const Ray& ray, RayCost& cost) const;

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;                // the root is node 0
  std::vector<std::uint32_t> references_;  // indices into triangles_, ascending within a leaf
  glm::dvec3 lo_{0.0};                     // the root cube's low corner
  double size_ = 0.0;                      // and its edge
  double pad_ = 0.0;
  int depth_ = 0;
};

}  // namespace rpu::accel
