#include "accel/bvh.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"
#include "common/error.hpp"

namespace rpu::accel {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

double half_area(const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 e = glm::max(hi - lo, glm::dvec3(0.0));
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

struct Bin {
  glm::dvec3 lo{kInf}, hi{-kInf};
  std::uint32_t count = 0;
};
}  // namespace

Bvh::Bvh(const TriangleSet& set) {
  const std::vector<Triangle>& input = set.triangles();
  if (input.empty()) return;
  std::vector<BuildItem> items(input.size());
  for (std::uint32_t i = 0; i < input.size(); ++i) {
    const Triangle& t = input[i];
    const glm::dvec3 v1 = t.v0 + t.e1, v2 = t.v0 + t.e2;
    const glm::dvec3 lo = glm::min(t.v0, glm::min(v1, v2)), hi = glm::max(t.v0, glm::max(v1, v2));
    items[i] = {lo, hi, 0.5 * (lo + hi), i};
  }
  nodes_.reserve(2 * input.size());
  build(items, 0, static_cast<std::uint32_t>(items.size()), 0, box_pad(set.bounds()));
  triangles_.reserve(items.size());
  for (const BuildItem& item : items) triangles_.push_back(input[item.triangle]);
}

std::uint32_t Bvh::build(std::vector<BuildItem>& items, std::uint32_t begin, std::uint32_t end, int depth,
                         double pad) {
  depth_ = std::max(depth_, depth);
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  glm::dvec3 lo(kInf), hi(-kInf), centroid_lo(kInf), centroid_hi(-kInf);
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = glm::min(lo, items[i].lo);
    hi = glm::max(hi, items[i].hi);
    centroid_lo = glm::min(centroid_lo, items[i].centroid);
    centroid_hi = glm::max(centroid_hi, items[i].centroid);
  }
  const std::uint32_t n = end - begin;
  auto make_leaf = [&] {
    nodes_[index] = {lo - pad, hi + pad, begin, static_cast<std::uint16_t>(n), 0};
    return index;
  };
  if (n == 1) return make_leaf();

  // Binned SAH: cost of a split = traversal + tests weighted by the children's areas.
  int best_axis = -1, best_split = 0;
  double best_cost = kInf;
  const glm::dvec3 centroid_extent = centroid_hi - centroid_lo;
  auto bin_of = [&](const BuildItem& item, int axis) {
    const double x = (item.centroid[axis] - centroid_lo[axis]) / centroid_extent[axis];
    return std::min(kBins - 1, static_cast<int>(kBins * x));
  };
  if (depth < kMaxSahDepth) {
    const double parent_area = half_area(lo, hi);
    for (int axis = 0; axis < 3; ++axis) {
      if (!(centroid_extent[axis] > 0.0)) continue;
      std::array<Bin, kBins> bins;
      for (std::uint32_t i = begin; i < end; ++i) {
        Bin& bin = bins[static_cast<std::size_t>(bin_of(items[i], axis))];
        bin.lo = glm::min(bin.lo, items[i].lo);
        bin.hi = glm::max(bin.hi, items[i].hi);
        ++bin.count;
      }
      // right_area[s], right_count[s]: of bins s..kBins-1.
      std::array<double, kBins> right_area{};
      std::array<std::uint32_t, kBins> right_count{};
      Bin right;
      for (int s = kBins - 1; s > 0; --s) {
        right.lo = glm::min(right.lo, bins[s].lo);
        right.hi = glm::max(right.hi, bins[s].hi);
        right.count += bins[s].count;
        right_area[s] = half_area(right.lo, right.hi);
        right_count[s] = right.count;
      }
      Bin left;
      for (int s = 1; s < kBins; ++s) {
        left.lo = glm::min(left.lo, bins[s - 1].lo);
        left.hi = glm::max(left.hi, bins[s - 1].hi);
        left.count += bins[s - 1].count;
        if (left.count == 0 || right_count[s] == 0) continue;
        const double cost = kTraversalCost + kTestCost * (half_area(left.lo, left.hi) * left.count +
                                                          right_area[s] * right_count[s]) / parent_area;
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = s;
        }
      }
    }
  }
  if (n <= kMaxLeafTriangles && (best_axis < 0 || kTestCost * n <= best_cost)) return make_leaf();

  std::uint32_t middle;
  int axis = best_axis;
  if (best_axis >= 0) {
    auto first_right = std::partition(items.begin() + begin, items.begin() + end,
                                      [&](const BuildItem& item) { return bin_of(item, axis) < best_split; });
    middle = static_cast<std::uint32_t>(first_right - items.begin());
  } else {
    // Too deep, or every centroid in one point: halve the list along the widest axis.
    axis = centroid_extent.x >= centroid_extent.y ? (centroid_extent.x >= centroid_extent.z ? 0 : 2)
                                                  : (centroid_extent.y >= centroid_extent.z ? 1 : 2);
    middle = begin + n / 2;
    std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
                     [&](const BuildItem& a, const BuildItem& b) {
                       return a.centroid[axis] < b.centroid[axis] ||
                              (a.centroid[axis] == b.centroid[axis] && a.triangle < b.triangle);
                     });
  }
  build(items, begin, middle, depth + 1, pad);
  const std::uint32_t second = build(items, middle, end, depth + 1, pad);
  nodes_[index] = {lo - pad, hi + pad, second, 0, static_cast<std::uint8_t>(axis)};
  return index;
}

std::string Bvh::parameters() const {
  return fmt::format("binned SAH, {} bins, leaves <= {}, depth {}", kBins, kMaxLeafTriangles, depth_);
}

Hit Bvh::closest_hit(const Ray& ray, RayCost& cost) const { return traverse<false>(ray, cost); }

bool Bvh::any_hit(const Ray& ray, RayCost& cost) const { return traverse<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit Bvh::traverse(const Ray& ray, RayCost& cost) const {
  Hit best;
  if (nodes_.empty()) return best;
  const glm::dvec3 inv = safe_reciprocal(ray.direction);
  std::array<std::uint32_t, kStackSize> stack;
  int top = 0;
  std::uint32_t current = 0;
  for (;;) {
    const Node& node = nodes_[current];
    ++cost.nodes;
    cost.bytes += kNodeBytes;
    // A box entered exactly at the best t is still visited: it may hold a tie of a
    // smaller primitive id.
    double t_near = ray.t_min, t_far = std::min(ray.t_max, best.t);
    if (clip_to_box(node.lo, node.hi, ray.origin, inv, t_near, t_far)) {
      if (node.count == 0) {
        if (inv[node.axis] < 0.0) {
          stack[static_cast<std::size_t>(top++)] = current + 1;
          current = node.offset;
        } else {
          stack[static_cast<std::size_t>(top++)] = node.offset;
          current = current + 1;
        }
        continue;
      }
      if (test_triangles<kAnyHit>(ray, std::span(triangles_).subspan(node.offset, node.count), best, cost)) {
        return best;
      }
    }
    if (top == 0) break;
    current = stack[static_cast<std::size_t>(--top)];
  }
  return best;
}

void Bvh::closest_hits_of_beam(std::span<const Ray> rays, const Frustum& frustum, std::span<Hit> hits,
                               BeamCost& cost) const {
  if (nodes_.empty() || rays.empty()) return;
  if (rays.size() > kMaxBeamRays || hits.size() != rays.size()) {
    throw Error(fmt::format("a beam of {} rays and {} hits; at most {} rays, one hit each", rays.size(), hits.size(),
                            kMaxBeamRays));
  }
  std::array<glm::dvec3, kMaxBeamRays> inv;
  for (std::size_t i = 0; i < rays.size(); ++i) inv[i] = safe_reciprocal(rays[i].direction);
  struct Pending {
    std::uint32_t node;
    std::uint64_t rays;  // bit i: rays[i] still walks this node
  };
  std::array<Pending, kStackSize> stack;
  int top = 0;
  Pending current{0, rays.size() == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << rays.size()) - 1};
  auto each_ray = [](std::uint64_t mask, auto&& f) {
    for (; mask != 0; mask &= mask - 1) f(static_cast<std::size_t>(std::countr_zero(mask)));
  };
  for (;;) {
    const Node& node = nodes_[current.node];
    ++cost.frustum_nodes;
    cost.bytes += kNodeBytes;
    std::uint64_t entering = 0;
    if (!frustum.misses_box(node.lo, node.hi)) {
      // Each ray's own test, as closest_hit makes it.
      each_ray(current.rays, [&](std::size_t i) {
        ++cost.ray_nodes;
        double t_near = rays[i].t_min, t_far = std::min(rays[i].t_max, hits[i].t);
        if (clip_to_box(node.lo, node.hi, rays[i].origin, inv[i], t_near, t_far)) entering |= std::uint64_t{1} << i;
      });
    }
    if (entering != 0 && node.count == 0) {
      // The child on the side the first entering ray comes from first.
      const bool second_first = inv[static_cast<std::size_t>(std::countr_zero(entering))][node.axis] < 0.0;
      stack[static_cast<std::size_t>(top++)] = {second_first ? current.node + 1 : node.offset, entering};
      current = {second_first ? node.offset : current.node + 1, entering};
      continue;
    }
    if (entering != 0) {
      for (std::uint32_t k = node.offset; k < node.offset + node.count; ++k) {
        const Triangle& tri = triangles_[k];
        ++cost.frustum_triangles;
        cost.bytes += kTriangleRecordBytes;
        if (frustum.misses_triangle(tri)) continue;
        each_ray(entering, [&](std::size_t i) {
          ++cost.ray_tests;
          double t;
          if (intersect(rays[i], tri, t) && hits[i].improved_by(t, tri.prim)) hits[i] = {t, tri.prim};
        });
      }
    }
    if (top == 0) break;
    current = stack[static_cast<std::size_t>(--top)];
  }
}

}  // namespace rpu::accel
