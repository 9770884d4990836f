#include "accel/bsp.hpp"

#include <algorithm>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"
#include "accel/split_plane_walk.hpp"
#include "accel/triangle_box.hpp"
#include "common/error.hpp"

namespace rpu::accel {

Bsp::Bsp(const TriangleSet& set) : triangles_(set.triangles()) {
  if (triangles_.empty()) return;
  pad_ = box_pad(set.bounds());
  lo_ = set.bounds().lo - pad_;
  hi_ = set.bounds().hi + pad_;
  std::vector<std::uint32_t> all(triangles_.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  build(lo_, hi_, 0, all);
}

// Subdivide: a leaf, or the box halved across axis depth mod 3 and each half subdivided.
std::uint32_t Bsp::build(const glm::dvec3& lo, const glm::dvec3& hi, int depth,
                         const std::vector<std::uint32_t>& items) {
  depth_ = std::max(depth_, depth);
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  if (items.size() <= kMaxLeafTriangles || depth >= kMaxDepth) {
    if (references_.size() + items.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error(fmt::format("bsp needs more than 2^32 references; the scene has {} triangles", triangles_.size()));
    }
    nodes_[index] = {static_cast<std::uint32_t>(references_.size()), static_cast<std::uint32_t>(items.size()), 0, 0.0};
    references_.insert(references_.end(), items.begin(), items.end());
    return index;
  }
  const int axis = depth % 3;
  const double split = 0.5 * (lo[axis] + hi[axis]);
  glm::dvec3 below_hi = hi, above_lo = lo;
  below_hi[axis] = split;
  above_lo[axis] = split;
  auto overlapping = [&](const glm::dvec3& box_lo, const glm::dvec3& box_hi) {
    std::vector<std::uint32_t> inside;
    for (const std::uint32_t k : items) {
      const Triangle& t = triangles_[k];
      if (triangle_overlaps_box(t.v0, t.v0 + t.e1, t.v0 + t.e2, box_lo - pad_, box_hi + pad_)) inside.push_back(k);
    }
    return inside;
  };
  build(lo, below_hi, depth + 1, overlapping(lo, below_hi));
  const std::uint32_t above = build(above_lo, hi, depth + 1, overlapping(above_lo, hi));
  nodes_[index] = {above, kInner, axis, split};
  return index;
}

std::string Bsp::parameters() const {
  return fmt::format("midpoint splits, axes in turn, leaves <= {} triangles or depth {}, depth {}, {:.2f} "
                     "refs/triangle",
                     kMaxLeafTriangles, kMaxDepth, depth_,
                     triangles_.empty() ? 0.0 : double(references_.size()) / double(triangles_.size()));
}

Hit Bsp::closest_hit(const Ray& ray, RayCost& cost) const { return traverse<false>(ray, cost); }

bool Bsp::any_hit(const Ray& ray, RayCost& cost) const { return traverse<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit Bsp::traverse(const Ray& ray, RayCost& cost) const {
  if (nodes_.empty()) return {};
  return walk_split_planes<kAnyHit, kMaxDepth + 1>(
      ray, lo_, hi_, triangles_, kNodeBytes, [&](std::uint32_t n) {
        const Node& node = nodes_[n];
        if (node.count != kInner) {
          return SplitPlaneNode{true, 0, 0.0, 0, 0, std::span(references_).subspan(node.index, node.count)};
        }
        return SplitPlaneNode{false, node.axis, node.split, n + 1, node.index, {}};
      },
      cost);
}

}  // namespace rpu::accel
