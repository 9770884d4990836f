#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/structure.hpp"

namespace rpu::accel {

// How an octree node places its three split planes.
enum class OctreeSplit {
  // At the node's middle: the classic octree (Glassner 1984). The root is the scene's box
  // made a cube, so every node is a cube and its planes follow from the root.
  kMidpoint,
  // Octree-R (Whang, Song, Chung and Shin 1995, "Octree-R: an adaptive octree for
  // efficient ray tracing"): on each axis separately, the plane of the least estimated
  // cost, the surface-area-weighted triangle counts of its two sides
  // SA(left) N(left) + SA(right) N(right), among kCostCandidates - 1 planes evenly
  // spaced across the node (the middle one included, and kept on a tie). The root is the
  // scene's box.
  kCost,
};

// An octree: a box split by three axis-aligned planes into eight octants until a node
// holds at most kMaxLeafTriangles triangles or lies kMaxDepth levels down (the two
// termination rules of the classic octree, kept by octree-R). A triangle goes into each
// octant the separating-axis test finds it overlapping (padded as box.hpp says).
// Traversal is front to back with an explicit stack: a node's segment of the ray is cut
// at its three planes into the (at most four) octants it crosses, in order; as in the
// grid, a leaf's hit ends the walk only if it lies within the leaf's t-range.
//
// Storage and byte model: the midpoint octree's node is 8 bytes (an inner node: the index
// of its first child, the eight children stored together; a leaf: its first reference
// and count); the octants' boxes follow from the root cube, so no planes are stored.
// Octree-R's node is 16 bytes: an inner node holds the index of its first child (its kind
// in a spare bit) and its three planes as fp32, a leaf its first reference and count. A
// reference is a 32-bit triangle index (4 bytes); a test reads the 36-byte triangle record.
class Octree final : public Structure {
 public:
  static constexpr int kMaxDepth = 10;
  static constexpr std::uint32_t kMaxLeafTriangles = 8;
  static constexpr int kCostCandidates = 32;  // octree-R: planes at k/32 of the node, k = 1..31
  static constexpr std::uint64_t kMidpointNodeBytes = 8;
  static constexpr std::uint64_t kCostNodeBytes = 16;

  explicit Octree(const TriangleSet& triangles, OctreeSplit split = OctreeSplit::kMidpoint);

  std::string_view name() const override { return split_ == OctreeSplit::kMidpoint ? "octree" : "octree-r"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override {
    return stored_bytes(nodes_.size(), node_bytes(), references_.size(), triangles_.size());
  }
  std::uint64_t node_count() const override { return nodes_.size(); }
  int depth() const { return depth_; }
  // The root's three planes (the root is inner: the scene has more than kMaxLeafTriangles).
  glm::dvec3 root_planes() const { return nodes_.front().split; }
  std::uint64_t node_bytes() const { return split_ == OctreeSplit::kMidpoint ? kMidpointNodeBytes : kCostNodeBytes; }

 private:
  struct Node {
    std::uint32_t first;  // inner: the first of its eight children; leaf: its first reference
    std::uint32_t count;  // leaf: its references; inner: kInner
    glm::dvec3 split;     // inner: the three planes
  };
  static constexpr std::uint32_t kInner = ~std::uint32_t{0};

  void build(std::uint32_t index, const glm::dvec3& lo, const glm::dvec3& hi, int depth,
             std::vector<std::uint32_t>& items);
  glm::dvec3 cost_split(const glm::dvec3& lo, const glm::dvec3& hi, const std::vector<std::uint32_t>& items) const;
  template <bool kAnyHit>
  Hit traverse(const Ray& ray, RayCost& cost) const;

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;                // the root is node 0
  std::vector<std::uint32_t> references_;  // indices into triangles_, ascending within a leaf
  OctreeSplit split_;
  glm::dvec3 lo_{0.0}, hi_{0.0};           // the root box
  double pad_ = 0.0;
  int depth_ = 0;
};

}  // namespace rpu::accel
