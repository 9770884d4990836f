#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "accel/box.hpp"
#include "accel/structure.hpp"

namespace rpu::accel {

// One node of a binary tree of axis-aligned split planes (a kd-tree, an axis-aligned
// BSP), as the walk below reads it.
struct SplitPlaneNode {
  bool leaf;
  int axis;            // inner: the split axis
  double split;        // inner: the plane, in world space
  std::uint32_t below, above;  // inner: the children on the low and the high side
  std::span<const std::uint32_t> references;  // leaf: indices into the triangles
};

// The front-to-back walk of such a tree with an explicit stack of (node, t_min, t_max):
// RayTreeIntersect (Sung and Shirley 1992, "Ray tracing with the BSP tree", Graphics
// Gems III; Havran's TA_B recursive walk; pbrt-v3's KdTreeAccel::Intersect). At an inner
// node the plane's t cuts the ray's segment: the child on the origin's side (an origin on
// the plane goes with its direction) is near, the other far; a plane behind the origin
// or beyond the segment leaves only the near child, one before the segment only the far
// child, else the far child is pushed with [t_plane, t_max] and the near child walked on
// [t_min, t_plane]. As in the grid, a leaf's hit ends the walk only when it lies before
// the next node's range. `node(i)` gives node i as a SplitPlaneNode; the root is node 0
// and [lo, hi] its box; kStackSize bounds the tree's depth; every node visited reads
// node_bytes.
template <bool kAnyHit, std::size_t kStackSize, typename NodeAt>
Hit walk_split_planes(const Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi,
                      const std::vector<Triangle>& triangles, std::uint64_t node_bytes, NodeAt node_at,
                      RayCost& cost) {
  Hit best;
  const RootSegment root = enter_root(lo, hi, ray);
  if (!root.entered) return best;
  const glm::dvec3& inv = root.inv;
  double t_near = root.t_near, t_far = root.t_far;

  struct Pending {
    std::uint32_t node;
    double t_near, t_far;
  };
  std::array<Pending, kStackSize> stack;
  std::size_t top = 0;
  std::uint32_t current = 0;
  for (;;) {
    // A hit before this node's range is final. A hit exactly at its entry is not: the
    // node may hold a tie of a smaller id.
    if (best.t < t_near) break;
    const SplitPlaneNode node = node_at(current);
    ++cost.nodes;
    cost.bytes += node_bytes;
    if (!node.leaf) {
      const double t_plane = (node.split - ray.origin[node.axis]) * inv[node.axis];
      const bool below_first = ray.origin[node.axis] < node.split ||
                               (ray.origin[node.axis] == node.split && ray.direction[node.axis] <= 0.0);
      const std::uint32_t first = below_first ? node.below : node.above;
      const std::uint32_t second = below_first ? node.above : node.below;
      if (t_plane > t_far || t_plane <= 0.0) {
        current = first;
      } else if (t_plane < t_near) {
        current = second;
      } else {
        stack[top++] = {second, t_plane, t_far};
        current = first;
        t_far = t_plane;
      }
      continue;
    }
    if (test_references<kAnyHit>(ray, triangles, node.references, best, cost)) return best;
    if (top == 0) break;
    const Pending& next = stack[--top];
    current = next.node;
    t_near = next.t_near;
    t_far = next.t_far;
  }
  return best;
}

}  // namespace rpu::accel
