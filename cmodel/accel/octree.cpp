#include "accel/octree.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"
#include "accel/triangle_box.hpp"
#include "common/error.hpp"

namespace rpu::accel {

Octree::Octree(const TriangleSet& set) : triangles_(set.triangles()) {
  if (triangles_.empty()) return;
  const Bounds& b = set.bounds();
  pad_ = box_pad(b);
  const glm::dvec3 extent = b.hi - b.lo;
  size_ = std::max({extent.x, extent.y, extent.z}) + 2.0 * pad_;
  lo_ = 0.5 * (b.lo + b.hi) - 0.5 * size_;
  std::vector<std::uint32_t> all(triangles_.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  nodes_.push_back({});
  build(0, lo_, size_, 0, all);
}

void Octree::build(std::uint32_t index, const glm::dvec3& lo, double size, int depth,
                   std::vector<std::uint32_t>& items) {
  depth_ = std::max(depth_, depth);
  if (items.size() <= kMaxLeafTriangles || depth >= kMaxDepth) {
    if (references_.size() + items.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error(fmt::format("octree needs more than 2^32 references; the scene has {} triangles",
                              triangles_.size()));
    }
    nodes_[index] = {static_cast<std::uint32_t>(references_.size()), static_cast<std::uint32_t>(items.size())};
    references_.insert(references_.end(), items.begin(), items.end());
    return;
  }
  const auto first = static_cast<std::uint32_t>(nodes_.size());
  nodes_[index] = {first, kInner};
  nodes_.resize(nodes_.size() + 8);
  const double half = 0.5 * size;
  // Octant i lies on the high side of axis a when bit a of i is set.
  for (std::uint32_t i = 0; i < 8; ++i) {
    const glm::dvec3 child_lo = lo + half * glm::dvec3(i & 1u, (i >> 1) & 1u, (i >> 2) & 1u);
    const glm::dvec3 box_lo = child_lo - pad_, box_hi = child_lo + half + pad_;
    std::vector<std::uint32_t> inside;
    for (const std::uint32_t k : items) {
      const Triangle& t = triangles_[k];
      if (triangle_overlaps_box(t.v0, t.v0 + t.e1, t.v0 + t.e2, box_lo, box_hi)) inside.push_back(k);
    }
    build(first + i, child_lo, half, depth + 1, inside);
  }
}

std::string Octree::parameters() const {
  return fmt::format("leaves <= {} triangles or depth {}, depth {}, {:.2f} refs/triangle", kMaxLeafTriangles,
                     kMaxDepth, depth_,
                     triangles_.empty() ? 0.0 : double(references_.size()) / double(triangles_.size()));
}

Hit Octree::closest_hit(const Ray& ray, RayCost& cost) const { return traverse<false>(ray, cost); }

bool Octree::any_hit(const Ray& ray, RayCost& cost) const { return traverse<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit Octree::traverse(const Ray& ray, RayCost& cost) const {
  Hit best;
  if (nodes_.empty()) return best;
  const glm::dvec3 inv = safe_reciprocal(ray.direction);
  double t_near = ray.t_min, t_far = ray.t_max;
  if (!clip_to_box(lo_, lo_ + size_, ray.origin, inv, t_near, t_far)) return best;

  struct Pending {
    std::uint32_t node;
    glm::dvec3 lo;
    double size, t_near, t_far;
  };
  // Each level pushes at most three octants (four crossed, one taken at once).
  std::array<Pending, 3 * kMaxDepth + 1> stack;
  int top = 0;
  Pending current{0, lo_, size_, t_near, t_far};
  for (;;) {
    // A hit before this node's range is final; one exactly at its entry is not (a tie of
    // a smaller id may lie here).
    if (best.t < current.t_near) break;
    const Node& node = nodes_[current.node];
    ++cost.nodes;
    cost.bytes += kNodeBytes;
    if (node.count == kInner) {
      const double half = 0.5 * current.size;
      const glm::dvec3 mid = current.lo + half;
      // The octant the segment starts in, and the t where it crosses each mid-plane.
      std::uint32_t octant = 0;
      std::array<std::pair<double, int>, 3> crossings;
      int n = 0;
      for (int a = 0; a < 3; ++a) {
        const double t_mid = (mid[a] - ray.origin[a]) * inv[a];
        bool high;
        if (ray.direction[a] > 0.0) {
          high = current.t_near >= t_mid;
        } else if (ray.direction[a] < 0.0) {
          high = current.t_near < t_mid;
        } else {
          high = ray.origin[a] >= mid[a];
        }
        if (high) octant |= 1u << a;
        if (ray.direction[a] != 0.0 && t_mid > current.t_near && t_mid < current.t_far) crossings[n++] = {t_mid, a};
      }
      // At most three: sorted by exchanges (std::sort on a 3-element array trips gcc 12's
      // -Warray-bounds under ASan).
      auto order = [&](int i, int j) {
        if (crossings[static_cast<std::size_t>(j)] < crossings[static_cast<std::size_t>(i)]) {
          std::swap(crossings[static_cast<std::size_t>(i)], crossings[static_cast<std::size_t>(j)]);
        }
      };
      if (n > 1) order(0, 1);
      if (n > 2) {
        order(1, 2);
        order(0, 1);
      }
      // The octants in the order the ray meets them; pushed last first.
      std::array<Pending, 4> sequence;
      double from = current.t_near;
      for (int k = 0; k <= n; ++k) {
        const double to = k < n ? crossings[k].first : current.t_far;
        const glm::dvec3 child_lo = current.lo + half * glm::dvec3(octant & 1u, (octant >> 1) & 1u, (octant >> 2) & 1u);
        sequence[k] = {node.first + octant, child_lo, half, from, to};
        if (k < n) octant ^= 1u << crossings[k].second;
        from = to;
      }
      for (int k = n; k > 0; --k) stack[static_cast<std::size_t>(top++)] = sequence[k];
      current = sequence[0];
      continue;
    }
    if (test_references<kAnyHit>(ray, triangles_, std::span(references_).subspan(node.first, node.count), best,
                                 cost)) {
      return best;
    }
    if (top == 0) break;
    current = stack[static_cast<std::size_t>(--top)];
  }
  return best;
}

}  // namespace rpu::accel
