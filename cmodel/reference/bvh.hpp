#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "scene/ray.hpp"
#include "scene/scene.hpp"

namespace rpu {

// The reference renderer's own acceleration structure: a bounding volume hierarchy in
// double precision, deliberately unlike the hardware's kd-tree so the two views share
// no traversal code. Median split on the longest centroid axis; O(N log N) build.
class ReferenceBvh {
 public:
  explicit ReferenceBvh(const Scene& scene);

  Hit closest_hit(const Ray& ray) const;
  bool any_hit(const Ray& ray) const;

  std::size_t node_count() const { return nodes_.size(); }

 private:
  struct Node {
    glm::dvec3 lo, hi;
    std::uint32_t first;  // leaf: first triangle in order_; inner: right child index
    std::uint32_t count;  // leaf: triangle count; inner: 0 (left child is next)
  };
  struct Triangle {
    glm::dvec3 v0, e1, e2;
  };

  std::uint32_t build(std::uint32_t begin, std::uint32_t end, std::vector<glm::dvec3>& centroids);
  template <bool kAnyHit>
  Hit traverse(const Ray& ray) const;

  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;    // in leaf order
  std::vector<std::uint32_t> order_;   // leaf order -> scene triangle index
};

}  // namespace rpu
