#include "accel/kd_tree.hpp"

#include <array>
#include <cmath>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"

namespace rpu::accel {

KdTreeStructure::KdTreeStructure(const TriangleSet& set) : triangles_(set.triangles()) {
  if (triangles_.empty()) return;  // the builder refuses an empty scene
  // The kept triangles as a scene of their own, three vertices each, in TriangleSet order.
  Scene kept;
  kept.source = "the triangles of the acceleration-structure comparison";
  kept.materials.push_back({});
  for (std::uint32_t i = 0; i < triangles_.size(); ++i) {
    const Triangle& t = triangles_[i];
    kept.positions.emplace_back(t.v0);
    kept.positions.emplace_back(t.v0 + t.e1);
    kept.positions.emplace_back(t.v0 + t.e2);
    kept.triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    kept.material_ids.push_back(0);
  }
  tree_ = build_kdtree(kept, kd_build_config_for("default"));
  splits_.resize(tree_.nodes.size());
  for (std::size_t n = 0; n < tree_.nodes.size(); ++n) {
    if (!tree_.nodes[n].is_leaf()) splits_[n] = std::ldexp(double(tree_.nodes[n].split()), tree_.scale_exponent);
  }
  const double pad = box_pad(set.bounds());
  for (int a = 0; a < 3; ++a) {
    lo_[a] = std::ldexp(double(tree_.bounds_lo[a]), tree_.scale_exponent) - pad;
    hi_[a] = std::ldexp(double(tree_.bounds_hi[a]), tree_.scale_exponent) + pad;
  }
}

std::string KdTreeStructure::parameters() const {
  return fmt::format("SAH (the memory image's, config default), depth {}, {:.2f} refs/triangle",
                     tree_.stats.max_depth,
                     triangles_.empty() ? 0.0 : double(tree_.prim_refs.size()) / double(triangles_.size()));
}

Hit KdTreeStructure::closest_hit(const Ray& ray, RayCost& cost) const { return traverse<false>(ray, cost); }

bool KdTreeStructure::any_hit(const Ray& ray, RayCost& cost) const { return traverse<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit KdTreeStructure::traverse(const Ray& ray, RayCost& cost) const {
  Hit best;
  if (tree_.nodes.empty()) return best;
  const glm::dvec3 inv = safe_reciprocal(ray.direction);
  double t_near = ray.t_min, t_far = ray.t_max;
  if (!clip_to_box(lo_, hi_, ray.origin, inv, t_near, t_far)) return best;

  struct Pending {
    std::uint32_t node;
    double t_near, t_far;
  };
  std::array<Pending, kKdMaxDepthLimit + 1> stack;
  int top = 0;
  std::uint32_t current = 0;
  for (;;) {
    // A hit before this node's range is final. A hit exactly at its entry is not: the
    // node may hold a tie of a smaller id.
    if (best.t < t_near) break;
    const KdNode& node = tree_.nodes[current];
    ++cost.nodes;
    cost.bytes += kNodeBytes;
    if (!node.is_leaf()) {
      const int axis = node.split_axis();
      const double split = splits_[current];
      const double t_plane = (split - ray.origin[axis]) * inv[axis];
      // The child on the origin's side first; an origin on the plane goes with its direction.
      const bool below_first =
          ray.origin[axis] < split || (ray.origin[axis] == split && ray.direction[axis] <= 0.0);
      const std::uint32_t first = below_first ? current + 1 : node.above_child();
      const std::uint32_t second = below_first ? node.above_child() : current + 1;
      if (t_plane > t_far || t_plane <= 0.0) {
        current = first;
      } else if (t_plane < t_near) {
        current = second;
      } else {
        stack[static_cast<std::size_t>(top++)] = {second, t_plane, t_far};
        current = first;
        t_far = t_plane;
      }
      continue;
    }
    if (test_references<kAnyHit>(ray, triangles_,
                                 std::span(tree_.prim_refs).subspan(node.first_prim_ref(), node.prim_count()), best,
                                 cost)) {
      return best;
    }
    if (top == 0) break;
    const Pending& next = stack[static_cast<std::size_t>(--top)];
    current = next.node;
    t_near = next.t_near;
    t_far = next.t_far;
  }
  return best;
}

}  // namespace rpu::accel
