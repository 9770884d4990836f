// SAH kd-tree construction in O(N log N) after Wald & Havran 2006, "On building fast
// kd-trees for ray tracing, and on doing that in O(N log N)" (W&H below), their
// O(N log N) algorithm: split events are generated and sorted once, each node sweeps
// its sorted event lists for the cheapest plane, classifies its triangles and splices
// the lists into its children keeping their order, re-generating events only for the
// triangles that straddle the plane.
//
// Every event position is an fp32 value and so is every candidate plane, so the counts
// the sweep evaluates are exactly the references the node gets, and the box a child
// covers is the box the traversal unit sees. A triangle is referenced on every side
// whose closed box it touches (docs/kdtree.md, "Conservative splits").
#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "kdtree/kdtree.hpp"
#include "rpu/spec.hpp"
#include "scene/geometry.hpp"

namespace rpu {

KdBuildConfig kd_build_config_for(const std::string& hardware_config) {
  std::string names;
  for (const spec::HardwareConfig& c : spec::kConfigs) {
    if (c.name == hardware_config) {
      KdBuildConfig config;
      config.max_depth = c.stack_depth;
      config.stack_depth = c.stack_depth;
      config.hardware_config = hardware_config;
      return config;
    }
    names += fmt::format("{}{}", names.empty() ? "" : ", ", c.name);
  }
  throw Error(fmt::format("unknown hardware config '{}'; choose one of {} (spec/configs.toml)",
                          hardware_config, names));
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Box {
  std::array<float, 3> lo{}, hi{};
};

double surface_area(const Box& b) {
  const double dx = double(b.hi[0]) - b.lo[0], dy = double(b.hi[1]) - b.lo[1],
               dz = double(b.hi[2]) - b.lo[2];
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

// A triangle's extent inside a node: the fp32 box its (clipped) geometry occupies.
using Extent = Box;

// W&H: one event per triangle end along an axis. Sorted by position, then kind
// (end < planar < start, as in W&H), then triangle, so the order is deterministic.
enum EventKind : std::uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };
constexpr std::uint32_t kTriBits = 30;
constexpr std::uint32_t kTriMask = (1u << kTriBits) - 1u;

struct Event {
  float pos;
  std::uint32_t code;  // kind << 30 | triangle

  std::uint32_t tri() const { return code & kTriMask; }
  std::uint32_t kind() const { return code >> kTriBits; }
  bool operator<(const Event& o) const { return pos < o.pos || (pos == o.pos && code < o.code); }
};

using EventLists = std::array<std::vector<Event>, 3>;

void add_events(EventLists& lists, const Extent& e, std::uint32_t tri) {
  for (int k = 0; k < 3; ++k) {
    if (e.lo[k] == e.hi[k]) {
      lists[k].push_back({e.lo[k], (kPlanar << kTriBits) | tri});
    } else {
      lists[k].push_back({e.lo[k], (kStart << kTriBits) | tri});
      lists[k].push_back({e.hi[k], (kEnd << kTriBits) | tri});
    }
  }
}

float round_down(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x) f = std::nextafter(f, -kInf);
  return f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = std::nextafter(f, kInf);
  return f;
}

// The box both extents cover.
Extent intersect(const Extent& a, const Box& b) {
  Extent r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::max(a.lo[k], b.lo[k]);
    r.hi[k] = std::min(a.hi[k], b.hi[k]);
  }
  return r;
}

// The neighbouring fp32 values of a finite float, as std::nextafter but inline: the
// sweep asks for two per event position.
float next_up(float x) {
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<std::uint32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits + 1 : bits - 1);
}
float next_down(float x) { return -next_up(-x); }

// Candidate split planes must survive the traversal unit's load: subnormals flush to
// zero there (ARCHITECTURE.md, "Numbers"), which would move the plane.
bool usable_split(float c) { return std::fpclassify(c) != FP_SUBNORMAL; }

enum class Side : std::uint8_t { kBoth, kBelow, kAbove };

struct Split {
  double cost = std::numeric_limits<double>::infinity();
  int axis = -1;
  float pos = 0.0f;
};

class Builder {
 public:
  Builder(const Scene& scene, const KdBuildConfig& config, KdTree& tree)
      : scene_(scene), config_(config), tree_(tree), sides_(scene.triangles.size()) {}

  void run(const Box& root) {
    const std::size_t n = scene_.triangles.size();
    bounds_.resize(n);
    EventLists events;
    for (EventLists::value_type& list : events) list.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      Extent& e = bounds_[i];
      for (int k = 0; k < 3; ++k) {
        e.lo[k] = kInf;
        e.hi[k] = -kInf;
      }
      for (int v = 0; v < 3; ++v) {
        const glm::vec3& p = scene_.positions[scene_.triangles[i][v]];
        for (int k = 0; k < 3; ++k) {
          e.lo[k] = std::min(e.lo[k], p[k]);
          e.hi[k] = std::max(e.hi[k], p[k]);
        }
      }
      add_events(events, e, static_cast<std::uint32_t>(i));
    }
    // W&H: the one sort; every node below keeps the order by splicing.
    for (EventLists::value_type& list : events) std::sort(list.begin(), list.end());
    if (must_be_leaf(n, 0)) {
      make_leaf(new_node(), triangles_of(events[0]));
    } else {
      build(std::move(events), root, n, 0);
    }
  }

 private:
  // W&H: sweep each axis's sorted events. At a position q holding pe ends, pp
  // planar and ps starts, with A = #(lo < q) and B = #(hi < q) seen so far, a plane
  // at fp32 value c references #(lo <= c) triangles below and #(hi >= c) above (the
  // conservative rule). Rather than at q itself, where both the planar triangles and
  // the ones ending or starting at q would go to both sides, the sweep tries
  // c = next_down(q): A below, N - B above (planar and starting triangles go above
  // only) and c = next_up(q): A + ps + pp below, N - B - pe - pp above (planar and
  // ending ones go below only). Choosing the cheaper of the two is W&H's planar side
  // rule moved off the plane by one ulp. When a neighbouring position
  // is exactly that ulp away, q itself is the plane between them and is tried instead.
  Split find_split(const EventLists& events, const Box& box, std::size_t n) const {
    // The sweep minimises bonus * (A_below * N_below + A_above * N_above) with A half a
    // child's surface area; the cost formula is applied to the winner only.
    double best_score = std::numeric_limits<double>::infinity();
    Split best;
    const double keep = 1.0 - config_.empty_bonus;
    const double total = static_cast<double>(n);
    for (int k = 0; k < 3; ++k) {
      if (!(box.lo[k] < box.hi[k])) continue;  // a flat node cannot be cut on this axis
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const double da = double(box.hi[a]) - box.lo[a], db = double(box.hi[b]) - box.lo[b];
      const double cap = da * db, side = da + db, lo = box.lo[k], hi = box.hi[k];
      const auto try_plane = [&](float c, double below, double above) {
        if (!(box.lo[k] < c && c < box.hi[k]) || !usable_split(c)) return;
        const double score = ((cap + (c - lo) * side) * below + (cap + (hi - c) * side) * above) *
                             (below == 0.0 || above == 0.0 ? keep : 1.0);
        if (score < best_score) {
          best_score = score;
          best.axis = k;
          best.pos = c == 0.0f ? 0.0f : c;
        }
      };
      const std::vector<Event>& ev = events[k];
      double starts_before = 0.0, ends_before = 0.0;
      std::size_t i = 0;
      float prev = -kInf;
      while (i < ev.size()) {
        const float q = ev[i].pos;
        double pe = 0.0, pp = 0.0, ps = 0.0;
        for (; i < ev.size() && ev[i].pos == q; ++i) {
          const std::uint32_t kind = ev[i].kind();
          pe += kind == kEnd;
          pp += kind == kPlanar;
          ps += kind == kStart;
        }
        const float next = i < ev.size() ? ev[i].pos : kInf;
        const float down = next_down(q), up = next_up(q);
        const double below_q = starts_before + ps + pp, above_q = total - ends_before;
        if (down != prev) try_plane(down, starts_before, above_q);
        if (up != next) try_plane(up, below_q, above_q - pe - pp);
        if (down == prev || up == next) try_plane(q, below_q, above_q);
        starts_before = below_q;
        ends_before += pe + pp;
        prev = q;
      }
    }
    if (best.axis >= 0) {
      best.cost = config_.traversal_cost + config_.intersection_cost * 2.0 * best_score / surface_area(box);
    }
    return best;
  }

  // W&H: a triangle goes below when its extent starts at or before the plane and
  // above when it ends at or after it; touching counts (the closed-box rule). One pass
  // suffices because a triangle's start event comes before its end event.
  void classify(const std::vector<Event>& ev, float split) {
    for (const Event& e : ev) {
      Side& side = sides_[e.tri()];
      switch (e.kind()) {
        case kStart:
          side = e.pos > split ? Side::kAbove : Side::kBoth;
          break;
        case kEnd:
          if (e.pos < split) side = Side::kBelow;
          break;
        default:  // planar
          side = e.pos < split ? Side::kBelow : e.pos > split ? Side::kAbove : Side::kBoth;
          break;
      }
    }
  }

  // The extent of a triangle that straddles a plane, inside one child's box: its
  // bounding box clipped to the child, or with perfect_splits the bounds of the triangle
  // clipped to the child (W&H's "perfect splits"; Sutherland-Hodgman in double).
  Extent child_extent(std::uint32_t tri, const Box& box) const {
    const Extent loose = intersect(bounds_[tri], box);
    if (!config_.perfect_splits) return loose;
    struct Vertex {
      glm::dvec3 p;
      bool exact;  // an input vertex: its fp32 coordinates need no margin
    };
    std::array<Vertex, 9> buffers[2];
    Vertex* poly = buffers[0].data();
    Vertex* clipped = buffers[1].data();
    std::size_t count = 3;
    double scale = 0.0;
    for (int v = 0; v < 3; ++v) {
      poly[v] = {glm::dvec3(scene_.positions[scene_.triangles[tri][v]]), true};
      for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs(poly[v].p[k]));
    }
    for (int k = 0; k < 3; ++k) scale = std::max({scale, std::abs(double(box.lo[k])), std::abs(double(box.hi[k]))});
    for (int plane = 0; plane < 6 && count > 0; ++plane) {
      const int k = plane / 2;
      const double at = plane % 2 == 0 ? box.lo[k] : box.hi[k];
      const double sign = plane % 2 == 0 ? 1.0 : -1.0;  // inside: sign * (x - at) >= 0
      // Most planes leave the polygon whole (the loose extent already lies inside).
      if ((plane % 2 == 0 ? bounds_[tri].lo[k] >= box.lo[k] : bounds_[tri].hi[k] <= box.hi[k])) continue;
      std::size_t out = 0;
      for (std::size_t v = 0; v < count; ++v) {
        const Vertex& cur = poly[v];
        const Vertex& nxt = poly[(v + 1) % count];
        const double dc = sign * (cur.p[k] - at), dn = sign * (nxt.p[k] - at);
        if (dc >= 0.0) clipped[out++] = cur;
        if ((dc >= 0.0) != (dn >= 0.0)) {
          Vertex x{cur.p + (dc / (dc - dn)) * (nxt.p - cur.p), false};
          x.p[k] = at;
          clipped[out++] = x;
        }
      }
      count = out;
      std::swap(poly, clipped);
    }
    if (count == 0) return loose;  // only a touch the clipping rounded away
    // Computed vertices carry double rounding error relative to `scale`; widen them by
    // far less than an fp32 ulp before rounding outward, so the extent stays conservative.
    const double margin = scale * 0x1p-40;
    Extent tight;
    for (int k = 0; k < 3; ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::size_t v = 0; v < count; ++v) {
        const double m = poly[v].exact ? 0.0 : margin;
        lo = std::min(lo, poly[v].p[k] - m);
        hi = std::max(hi, poly[v].p[k] + m);
      }
      tight.lo[k] = round_down(lo);
      tight.hi[k] = round_up(hi);
    }
    return intersect(tight, loose);
  }

  // One pass over a parent list: each one-sided event is merged with that side's new
  // (sorted) straddler events straight into the child list, so every event is written
  // once. A null output is a child that becomes a leaf and needs no events.
  std::pair<Event*, Event*> splice(const std::vector<Event>& parent, const std::vector<Event>& new_below,
                                   const std::vector<Event>& new_above, Event* below, Event* above) const {
    auto nb = new_below.begin(), na = new_above.begin();
    for (const Event& e : parent) {
      const Side s = sides_[e.tri()];
      if (s == Side::kBelow && below != nullptr) {
        for (; nb != new_below.end() && *nb < e; ++nb) *below++ = *nb;
        *below++ = e;
      } else if (s == Side::kAbove && above != nullptr) {
        for (; na != new_above.end() && *na < e; ++na) *above++ = *na;
        *above++ = e;
      }
    }
    return {below == nullptr ? below : std::copy(nb, new_below.end(), below),
            above == nullptr ? above : std::copy(na, new_above.end(), above)};
  }

  bool must_be_leaf(std::size_t n, int depth) const {
    return n <= config_.max_leaf_prims || depth >= config_.max_depth;
  }

  // A leaf's triangles: one start or planar event per triangle in any axis list.
  static std::vector<std::uint32_t> triangles_of(const std::vector<Event>& ev) {
    std::vector<std::uint32_t> tris;
    for (const Event& e : ev) {
      if (e.kind() != kEnd) tris.push_back(e.tri());
    }
    return tris;
  }

  void make_leaf(std::uint32_t index, const std::vector<std::uint32_t>& tris) {
    const std::size_t first = tree_.prim_refs.size();
    if (tris.size() > KdNode::kMaxIndex || first + tris.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error(fmt::format("kd-tree for '{}' needs more primitive references than the kd-node "
                              "fields hold; raise max_leaf_prims or lower max_depth",
                              scene_.source));
    }
    tree_.prim_refs.insert(tree_.prim_refs.end(), tris.begin(), tris.end());
    tree_.nodes[index] = KdNode::leaf(static_cast<std::uint32_t>(tris.size()), static_cast<std::uint32_t>(first));
  }

  std::uint32_t new_node() {
    const std::size_t index = tree_.nodes.size();
    if (index > KdNode::kMaxIndex) {
      throw Error(fmt::format("kd-tree for '{}' needs more than {} nodes, more than the kd-node "
                              "index field holds; raise max_leaf_prims or lower max_depth",
                              scene_.source, KdNode::kMaxIndex + 1ull));
    }
    tree_.nodes.emplace_back();
    return static_cast<std::uint32_t>(index);
  }

  // Builds the subtree of a node that may be split; `events` are its sorted lists.
  void build(EventLists events, const Box& box, std::size_t n, int depth) {
    const std::uint32_t index = new_node();
    const Split split = find_split(events, box, n);
    // W&H's automatic termination: split only when it is cheaper than intersecting all n.
    if (split.axis < 0 || split.cost >= config_.intersection_cost * static_cast<double>(n)) {
      make_leaf(index, triangles_of(events[0]));
      return;
    }
    const int k = split.axis;
    classify(events[k], split.pos);

    Box below_box = box, above_box = box;
    below_box.hi[k] = split.pos;
    above_box.lo[k] = split.pos;

    std::vector<std::uint32_t> straddlers;
    std::size_t n_below = 0, n_above = 0;
    for (const Event& e : events[k]) {
      if (e.kind() == kEnd) continue;  // one start or planar event per triangle
      const Side s = sides_[e.tri()];
      n_below += s != Side::kAbove;
      n_above += s != Side::kBelow;
      if (s == Side::kBoth) straddlers.push_back(e.tri());
    }
    // A child that will be a leaf needs only its triangles, not events.
    const bool below_leaf = must_be_leaf(n_below, depth + 1), above_leaf = must_be_leaf(n_above, depth + 1);
    std::vector<std::uint32_t> below_tris, above_tris;
    for (const Event& e : events[k]) {
      if (e.kind() == kEnd) continue;
      const Side s = sides_[e.tri()];
      if (below_leaf && s != Side::kAbove) below_tris.push_back(e.tri());
      if (above_leaf && s != Side::kBelow) above_tris.push_back(e.tri());
    }

    // W&H: triangles on one side keep their events, in order; straddlers get new
    // events for each child, sorted on their own (few) and merged in.
    EventLists new_below, new_above, below, above;
    for (const std::uint32_t t : straddlers) {
      if (!below_leaf) add_events(new_below, child_extent(t, below_box), t);
      if (!above_leaf) add_events(new_above, child_extent(t, above_box), t);
    }
    if (!below_leaf || !above_leaf) {
      for (int axis = 0; axis < 3; ++axis) {
        std::sort(new_below[axis].begin(), new_below[axis].end());
        std::sort(new_above[axis].begin(), new_above[axis].end());
        // At most two events per one-sided triangle; the lists are cut to size after
        // the splice, which saves a counting pass over the parent list.
        if (!below_leaf) below[axis].resize(2 * (n_below - straddlers.size()) + new_below[axis].size());
        if (!above_leaf) above[axis].resize(2 * (n_above - straddlers.size()) + new_above[axis].size());
        const auto [end_below, end_above] =
            splice(events[axis], new_below[axis], new_above[axis], below_leaf ? nullptr : below[axis].data(),
                   above_leaf ? nullptr : above[axis].data());
        below[axis].resize(static_cast<std::size_t>(end_below - below[axis].data()));
        above[axis].resize(static_cast<std::size_t>(end_above - above[axis].data()));
        std::vector<Event>().swap(events[axis]);
      }
    }

    if (below_leaf) {
      make_leaf(new_node(), below_tris);
    } else {
      build(std::move(below), below_box, n_below, depth + 1);
    }
    const std::uint32_t above_index = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes[index] = KdNode::inner(k, above_index, split.pos);
    if (above_leaf) {
      make_leaf(new_node(), above_tris);
    } else {
      build(std::move(above), above_box, n_above, depth + 1);
    }
  }

  const Scene& scene_;
  const KdBuildConfig& config_;
  KdTree& tree_;
  std::vector<Side> sides_;
  std::vector<Extent> bounds_;  // each triangle's bounding box, fp32 (exact)
};

void check_config(const Scene& scene, const KdBuildConfig& c) {
  if (c.max_depth > c.stack_depth) {
    throw Error(fmt::format("kd-tree max depth {} exceeds the traversal stack depth {} of config "
                            "'{}'; lower --max-depth or choose a config with a deeper stack",
                            c.max_depth, c.stack_depth, c.hardware_config));
  }
  if (c.max_depth < 0 || c.max_depth > kKdMaxDepthLimit) {
    throw Error(fmt::format("kd-tree max depth {} is outside [0, {}]; choose a depth in that range "
                            "(and no deeper than the traversal stack)",
                            c.max_depth, kKdMaxDepthLimit));
  }
  if (!(c.traversal_cost >= 0.0) || !(c.intersection_cost >= 0.0) || !std::isfinite(c.traversal_cost) ||
      !std::isfinite(c.intersection_cost)) {
    throw Error(fmt::format("kd-tree costs must be finite and >= 0 (traversal {}, intersection {}); "
                            "fix the cost settings",
                            c.traversal_cost, c.intersection_cost));
  }
  if (!(c.empty_bonus >= 0.0 && c.empty_bonus < 1.0)) {
    throw Error(fmt::format("kd-tree empty bonus {} is outside [0, 1); choose a value in that range",
                            c.empty_bonus));
  }
  if (c.max_leaf_prims > KdNode::kMaxIndex) {
    throw Error(fmt::format("kd-tree max leaf primitives {} exceeds the kd-node count field ({}); "
                            "choose a smaller value",
                            c.max_leaf_prims, KdNode::kMaxIndex));
  }
  if (scene.triangles.empty()) {
    throw Error(fmt::format("scene '{}' has no triangles to build a kd-tree over; add geometry",
                            scene.source));
  }
  if (scene.triangles.size() > kTriMask + 1ull) {
    throw Error(fmt::format("scene '{}' has {} triangles, more than the kd-tree builder indexes "
                            "({}); split the scene",
                            scene.source, scene.triangles.size(), kTriMask + 1ull));
  }
}

// Walks the finished tree for its statistics and its SAH cost (MacDonald & Booth's
// expected cost without the empty bonus, which only steers the build).
void compute_stats(KdTree& tree, const KdBuildConfig& config) {
  KdTreeStats& s = tree.stats;
  s.nodes = tree.nodes.size();
  s.prim_refs = tree.prim_refs.size();
  s.bytes = spec::memory::kKdNodeBytes * s.nodes + 4 * s.prim_refs;
  struct Item {
    std::uint32_t index;
    Box box;
    int depth;
  };
  Box root;
  for (int k = 0; k < 3; ++k) {
    root.lo[k] = tree.bounds_lo[k];
    root.hi[k] = tree.bounds_hi[k];
  }
  const double inv_root_area = 1.0 / surface_area(root);
  std::vector<Item> stack{{0, root, 0}};
  double depth_sum = 0.0, cost = 0.0;
  std::uint64_t nonempty_refs = 0;
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const KdNode node = tree.nodes[item.index];
    const double p = surface_area(item.box) * inv_root_area;
    if (node.is_leaf()) {
      ++s.leaves;
      s.empty_leaves += node.prim_count() == 0;
      nonempty_refs += node.prim_count();
      depth_sum += item.depth;
      s.max_depth = std::max(s.max_depth, item.depth);
      cost += config.intersection_cost * p * node.prim_count();
      continue;
    }
    cost += config.traversal_cost * p;
    const int k = node.split_axis();
    Item below{item.index + 1, item.box, item.depth + 1}, above{node.above_child(), item.box, item.depth + 1};
    below.box.hi[k] = node.split();
    above.box.lo[k] = node.split();
    stack.push_back(above);
    stack.push_back(below);
  }
  s.mean_leaf_depth = depth_sum / static_cast<double>(s.leaves);
  const std::uint64_t nonempty = s.leaves - s.empty_leaves;
  s.mean_prims_per_leaf = nonempty == 0 ? 0.0 : static_cast<double>(nonempty_refs) / static_cast<double>(nonempty);
  s.sah_cost = cost;
}

}  // namespace

KdTree build_kdtree(const Scene& scene, const KdBuildConfig& config) {
  check_config(scene, config);
  const auto start = std::chrono::steady_clock::now();
  KdTree tree;
  // Vertices are fp32, so the scene box is exact in fp32; rounding outward only
  // guards that claim.
  const Bounds b = scene_bounds(scene);
  Box root;
  for (int k = 0; k < 3; ++k) {
    root.lo[k] = round_down(b.lo[k]);
    root.hi[k] = round_up(b.hi[k]);
  }
  tree.bounds_lo = glm::vec3(root.lo[0], root.lo[1], root.lo[2]);
  tree.bounds_hi = glm::vec3(root.hi[0], root.hi[1], root.hi[2]);
  Builder(scene, config, tree).run(root);
  tree.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  compute_stats(tree, config);
  return tree;
}

std::string format_kd_stats(const KdTreeStats& s) {
  const std::uint64_t inner = s.nodes - s.leaves;
  return fmt::format(
      "nodes            {} ({} inner, {} leaves, {} empty)\n"
      "depth            max {}, mean leaf {:.2f}\n"
      "prims per leaf   {:.2f} (non-empty leaves)\n"
      "prim refs        {}\n"
      "SAH cost         {:.2f}\n"
      "memory           {} bytes ({:.2f} MiB)\n"
      "build time       {:.3f} s\n",
      s.nodes, inner, s.leaves, s.empty_leaves, s.max_depth, s.mean_leaf_depth, s.mean_prims_per_leaf,
      s.prim_refs, s.sah_cost, s.bytes, static_cast<double>(s.bytes) / (1024.0 * 1024.0), s.build_seconds);
}

}  // namespace rpu
