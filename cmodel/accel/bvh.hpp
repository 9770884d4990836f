#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "accel/beam.hpp"
#include "accel/structure.hpp"

namespace rpu::accel {

// A bounding volume hierarchy of axis-aligned boxes (a hierarchy of bounding volumes,
// Kay and Kajiya 1986), built top-down by the surface area heuristic over centroid bins
// (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies").
// Traversal is front to back with an explicit stack: of an inner node's two children the
// one on the ray's side of the split axis first (pbrt-v3, BVHAccel::Intersect).
//
// Storage and byte model: a node is 32 bytes as a chip stores it (pbrt's LinearBVHNode:
// six fp32 bounds, a 32-bit child or first-triangle offset, a 16-bit triangle count, the
// split axis), read whole on every visit; the triangles are stored in leaf order, so a
// leaf needs no references and a test reads one 36-byte record.
class Bvh final : public Structure {
 public:
  static constexpr int kBins = 16;               // SAH candidate planes: bin boundaries per axis
  static constexpr int kMaxLeafTriangles = 8;    // a larger node is always split
  static constexpr double kTraversalCost = 1.0;  // of one node step, in units of ...
  static constexpr double kTestCost = 1.0;       // ... one ray/triangle test
  // Past this depth nodes are split at the object median, so the stack bound below holds
  // for any input (a median split halves the count: at most 32 more levels).
  static constexpr int kMaxSahDepth = 64;
  static constexpr int kStackSize = kMaxSahDepth + 34;
  static constexpr std::uint64_t kNodeBytes = 32;

  explicit Bvh(const TriangleSet& triangles);

  std::string_view name() const override { return "bvh"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override {
    return stored_bytes(nodes_.size(), kNodeBytes, 0, triangles_.size());
  }
  std::uint64_t node_count() const override { return nodes_.size(); }
  int depth() const { return depth_; }
  // The closest hits of a beam of at most kMaxBeamRays rays (beam.hpp): hits[i] of
  // rays[i], each exactly as closest_hit finds it.
  void closest_hits_of_beam(std::span<const Ray> rays, const Frustum& frustum, std::span<Hit> hits,
                            BeamCost& cost) const;

 private:
  struct Node {
    glm::dvec3 lo, hi;
    std::uint32_t offset;  // inner: the second child (the first follows the node); leaf: first triangle
    std::uint16_t count;   // leaf: its triangles; inner: 0
    std::uint8_t axis;     // inner: the split axis
  };
  struct BuildItem {
    glm::dvec3 lo, hi, centroid;
    std::uint32_t triangle;  // index into the input triangles
  };

  std::uint32_t build(std::vector<BuildItem>& items, std::uint32_t begin, std::uint32_t end, int depth, double pad);
  template <bool kAnyHit>
  Hit traverse(const Ray& ray, RayCost& cost) const;

  std::vector<Node> nodes_;          // depth first; the root is node 0
  std::vector<Triangle> triangles_;  // in leaf order
  int depth_ = 0;
};

}  // namespace rpu::accel
