#include "accel/kd_tree.hpp"

#include <cmath>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"
#include "accel/split_plane_walk.hpp"

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
  if (tree_.nodes.empty()) return {};
  return walk_split_planes<kAnyHit, kKdMaxDepthLimit + 1>(
      ray, lo_, hi_, triangles_, kNodeBytes, [&](std::uint32_t n) {
        const KdNode& node = tree_.nodes[n];
        if (node.is_leaf()) {
          return SplitPlaneNode{true, 0, 0.0, 0, 0,
                                std::span(tree_.prim_refs).subspan(node.first_prim_ref(), node.prim_count())};
        }
        return SplitPlaneNode{false, node.split_axis(), splits_[n], n + 1, node.above_child(), {}};
      },
      cost);
}

}  // namespace rpu::accel
