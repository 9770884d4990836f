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

Octree::Octree(const TriangleSet& set, OctreeSplit split) : triangles_(set.triangles()), split_(split) {
  if (triangles_.empty()) return;
  const Bounds& b = set.bounds();
  pad_ = box_pad(b);
  if (split_ == OctreeSplit::kMidpoint) {
    const glm::dvec3 extent = b.hi - b.lo;
    const double size = std::max({extent.x, extent.y, extent.z}) + 2.0 * pad_;
    lo_ = 0.5 * (b.lo + b.hi) - 0.5 * size;
    hi_ = lo_ + size;
  } else {
    lo_ = b.lo - pad_;
    hi_ = b.hi + pad_;
  }
  std::vector<std::uint32_t> all(triangles_.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  nodes_.push_back({});
  build(0, lo_, hi_, 0, all);
}

glm::dvec3 Octree::cost_split(const glm::dvec3& lo, const glm::dvec3& hi,
                              const std::vector<std::uint32_t>& items) const {
  constexpr int kBins = kCostCandidates;
  const glm::dvec3 extent = hi - lo;
  glm::dvec3 split = lo + 0.5 * extent;
  for (int a = 0; a < 3; ++a) {
    // Per bin, the triangles whose box (clipped to the node) starts in it and ends in it;
    // plane k (at lo + k/kBins of the extent) has on its low side those starting in a bin
    // below k, on its high side those ending in bin k or above.
    std::array<std::uint32_t, kBins> starts{}, ends{};
    // Clamped before the conversion: a triangle reaching far past the node (or a flat
    // node's NaN) would not fit an int, and converting it is undefined.
    auto bin = [&](double x) {
      const double at = (x - lo[a]) / extent[a] * kBins;
      return at >= kBins - 1 ? kBins - 1 : at >= 0.0 ? static_cast<int>(at) : 0;
    };
    for (const std::uint32_t k : items) {
      const Triangle& t = triangles_[k];
      const double v1 = t.v0[a] + t.e1[a], v2 = t.v0[a] + t.e2[a];
      ++starts[static_cast<std::size_t>(bin(std::min({t.v0[a], v1, v2})))];
      ++ends[static_cast<std::size_t>(bin(std::max({t.v0[a], v1, v2})))];
    }
    // Areas are half surface areas: the two faces across the axis and the sides' lengths.
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double across = extent[b] * extent[c], around = extent[b] + extent[c];
    auto cost = [&](int k, std::uint32_t low, std::uint32_t high) {
      const double low_length = extent[a] * k / kBins, high_length = extent[a] - low_length;
      return (across + low_length * around) * low + (across + high_length * around) * high;
    };
    std::array<std::uint32_t, kBins + 1> low{}, high{};  // low[k], high[k]: the two sides of plane k
    for (int k = 1; k <= kBins; ++k) low[k] = low[k - 1] + starts[static_cast<std::size_t>(k - 1)];
    for (int k = kBins - 1; k >= 0; --k) high[k] = high[k + 1] + ends[static_cast<std::size_t>(k)];
    int best = kBins / 2;
    double best_cost = cost(best, low[best], high[best]);
    for (int k = 1; k < kBins; ++k) {
      const double c_k = cost(k, low[k], high[k]);
      if (c_k < best_cost) {
        best_cost = c_k;
        best = k;
      }
    }
    if (best != kBins / 2) split[a] = lo[a] + extent[a] * best / kBins;
  }
  return split;
}

void Octree::build(std::uint32_t index, const glm::dvec3& lo, const glm::dvec3& hi, int depth,
                   std::vector<std::uint32_t>& items) {
  depth_ = std::max(depth_, depth);
  if (items.size() <= kMaxLeafTriangles || depth >= kMaxDepth) {
    if (references_.size() + items.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error(fmt::format("{} needs more than 2^32 references; the scene has {} triangles", name(),
                              triangles_.size()));
    }
    nodes_[index] = {static_cast<std::uint32_t>(references_.size()), static_cast<std::uint32_t>(items.size()), {}};
    references_.insert(references_.end(), items.begin(), items.end());
    return;
  }
  const glm::dvec3 split = split_ == OctreeSplit::kMidpoint ? 0.5 * (lo + hi) : cost_split(lo, hi, items);
  const auto first = static_cast<std::uint32_t>(nodes_.size());
  nodes_[index] = {first, kInner, split};
  nodes_.resize(nodes_.size() + 8);
  // Octant i lies on the high side of axis a when bit a of i is set.
  for (std::uint32_t i = 0; i < 8; ++i) {
    glm::dvec3 child_lo, child_hi;
    for (int a = 0; a < 3; ++a) {
      const bool high = (i >> a) & 1u;
      child_lo[a] = high ? split[a] : lo[a];
      child_hi[a] = high ? hi[a] : split[a];
    }
    std::vector<std::uint32_t> inside;
    for (const std::uint32_t k : items) {
      const Triangle& t = triangles_[k];
      if (triangle_overlaps_box(t.v0, t.v0 + t.e1, t.v0 + t.e2, child_lo - pad_, child_hi + pad_)) {
        inside.push_back(k);
      }
    }
    build(first + i, child_lo, child_hi, depth + 1, inside);
  }
}

std::string Octree::parameters() const {
  return fmt::format("{}, leaves <= {} triangles or depth {}, depth {}, {:.2f} refs/triangle",
                     split_ == OctreeSplit::kMidpoint ? "midpoint splits" : "SAH planes per axis", kMaxLeafTriangles,
                     kMaxDepth, depth_,
                     triangles_.empty() ? 0.0 : double(references_.size()) / double(triangles_.size()));
}

Hit Octree::closest_hit(const Ray& ray, RayCost& cost) const { return traverse<false>(ray, cost); }

bool Octree::any_hit(const Ray& ray, RayCost& cost) const { return traverse<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit Octree::traverse(const Ray& ray, RayCost& cost) const {
  Hit best;
  if (nodes_.empty()) return best;
  const RootSegment root = enter_root(lo_, hi_, ray);
  if (!root.entered) return best;
  const glm::dvec3& inv = root.inv;

  struct Pending {
    std::uint32_t node;
    double t_near, t_far;
  };
  // Each level pushes at most three octants (four crossed, one taken at once).
  std::array<Pending, 3 * kMaxDepth + 1> stack;
  int top = 0;
  Pending current{0, root.t_near, root.t_far};
  for (;;) {
    // A hit before this node's range is final; one exactly at its entry is not (a tie of
    // a smaller id may lie here).
    if (best.t < current.t_near) break;
    const Node& node = nodes_[current.node];
    ++cost.nodes;
    cost.bytes += node_bytes();
    if (node.count == kInner) {
      const glm::dvec3& mid = node.split;
      // The octant the segment starts in, and the t where it crosses each plane.
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
        sequence[k] = {node.first + octant, from, to};
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
