// SAH kd-tree construction in O(N log N) after Wald & Havran 2006, "On building fast
// kd-trees for ray tracing, and on doing that in O(N log N)" (W&H below), their
// O(N log N) algorithm: split events are generated and sorted once, each node sweeps
// its sorted event lists for the cheapest plane, classifies its triangles and splices
// the lists into its children keeping their order, re-generating events only for the
// triangles that straddle the plane.
//
// Every event position and every candidate plane is a value of the configured number
// format (zero or normal, held as fp32), so the counts the sweep evaluates are exactly
// the references the node gets, and the box a child covers is the box the traversal
// unit sees after rounding into the format. A triangle, as its vertices rounded into the
// format and widened by a margin, is referenced on every side whose closed box it
// touches (docs/kdtree.md, "Conservative splits in any format").
#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "fp/soft.hpp"
#include "kdtree/kdtree.hpp"
#include "rpu/spec.hpp"
#include "scene/geometry.hpp"

namespace rpu {

KdBuildConfig kd_build_config_for(const std::string& name) { return kd_build_config_for(hardware_config(name)); }

KdBuildConfig kd_build_config_for(const spec::HardwareConfig& c) {
  KdBuildConfig config;
  config.max_depth = c.stack_depth;
  config.stack_depth = c.stack_depth;
  config.format = fp::format_by_name(c.format);
  config.hardware_config = c.name;
  return config;
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

double surface_area(const Bounds32& b) {
  const double dx = double(b.hi[0]) - b.lo[0], dy = double(b.hi[1]) - b.lo[1],
               dz = double(b.hi[2]) - b.lo[2];
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

// A triangle's extent inside a node: the fp32 box its (clipped) geometry occupies.
using Extent = Bounds32;

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

// An allocator that default-initialises where std::allocator value-initialises, so that
// an event list resized for the splice to overwrite is not zeroed first.
template <class T>
struct UninitialisedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
};

using EventList = std::vector<Event, UninitialisedAllocator<Event>>;
using EventLists = std::array<EventList, 3>;

// Lists shorter than this are sorted by comparison; a radix sort's per-pass setup
// costs more than it saves there.
constexpr std::size_t kRadixSortMin = 64;

// An event's (position, kind) as an unsigned integer in the same order: the
// position's fp32 bits with negative values flipped (and -0 taken as +0, which the
// float comparison treats as equal), then the kind in two bits.
std::uint64_t position_kind_key(const Event& e) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(e.pos + 0.0f);
  const std::uint32_t ordered = bits ^ ((std::uint32_t{0} - (bits >> 31)) | 0x80000000u);
  return (std::uint64_t{ordered} << 2) | e.kind();
}

// Sorts a list generated in triangle order into W&H's event order. Long lists get an
// LSD radix sort by (position, kind) on bytes, skipping the bytes all events share;
// it is stable, so the triangle order breaks ties as the comparison does. The radix
// sort has no data-dependent branches, where a comparison sort mispredicts about one
// comparison in two. `scratch` is its buffer, reused across calls.
void sort_events(EventList& ev, EventList& scratch) {
  if (ev.size() < kRadixSortMin) {
    std::sort(ev.begin(), ev.end());
    return;
  }
  constexpr int kBytes = 5;  // 34 key bits
  std::array<std::array<std::uint32_t, 256>, kBytes> counts{};
  for (const Event& e : ev) {
    const std::uint64_t key = position_kind_key(e);
    for (int b = 0; b < kBytes; ++b) ++counts[b][(key >> (8 * b)) & 0xff];
  }
  scratch.resize(ev.size());
  const std::uint64_t first_key = position_kind_key(ev.front());
  for (int b = 0; b < kBytes; ++b) {
    std::array<std::uint32_t, 256>& offset = counts[b];
    if (offset[(first_key >> (8 * b)) & 0xff] == ev.size()) continue;  // every event has this byte
    std::uint32_t sum = 0;
    for (std::uint32_t& c : offset) sum += std::exchange(c, sum);
    for (const Event& e : ev) scratch[offset[(position_kind_key(e) >> (8 * b)) & 0xff]++] = e;
    ev.swap(scratch);
  }
}

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

// The float after and before a finite float, as std::nextafter gives them, inline.
float float_above(float f) {
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits + 1 : bits - 1);
}
float float_below(float f) { return -float_above(-f); }

float round_down(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x) f = float_below(f);
  return f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = float_above(f);
  return f;
}

// The box both extents cover.
Extent intersect(const Extent& a, const Bounds32& b) {
  Extent r;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = std::max(a.lo[k], b.lo[k]);
    r.hi[k] = std::min(a.hi[k], b.hi[k]);
  }
  return r;
}

float as_float(fp::Format f, std::uint32_t bits) { return std::bit_cast<float>(fp::soft::to_fp32(f, bits)); }

// The fp32 values the traversal unit loads unchanged in a format: zero and the format's
// normal numbers. A subnormal would flush to zero and any other value would round
// (docs/numbers.md, from_fp32), moving the plane. Event positions and planes stay on
// this grid, so every plane the sweep costs is the plane the unit compares against.
class Grid {
 public:
  explicit Grid(fp::Format f)
      : step_(std::uint32_t{1} << (23 - f.fraction_bits)),
        min_normal_(as_float(f, f.min_normal(false))),
        max_finite_(as_float(f, f.max_finite(false))) {}

  float max_finite() const { return max_finite_; }
  // One unit in the format's last place, in fp32 fraction bits: the distance between
  // the bits of neighbouring normal numbers of one sign (a carry moves to the next
  // binade).
  std::uint32_t step() const { return step_; }
  // The largest grid value <= x and the smallest >= x, for finite x within the
  // format's range (the builder checks the range before it rounds).
  float down(float x) const {
    if (x < 0.0f) return -up(-x);
    const float t = std::bit_cast<float>(std::bit_cast<std::uint32_t>(x) & ~(step_ - 1));
    return t < min_normal_ ? 0.0f : t;
  }
  float up(float x) const {
    if (x <= 0.0f) return 0.0f - down(-x);  // 0 - (+0) keeps zero positive
    std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    if ((bits & (step_ - 1)) != 0) bits = (bits | (step_ - 1)) + 1;  // a carry moves to the next binade
    const float t = std::bit_cast<float>(bits);
    return t < min_normal_ ? min_normal_ : t;
  }
  // The grid neighbours of a grid value; the sweep asks for two per event position.
  float next_up(float q) const {
    if (q < 0.0f) return 0.0f - lower(-q);  // 0 - (+0) keeps zero positive
    if (q == 0.0f) return min_normal_;
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(q) + step_);
  }
  float next_down(float q) const { return 0.0f - next_up(-q); }

 private:
  // The grid value below a positive grid value q.
  float lower(float q) const {
    return q == min_normal_ ? 0.0f : std::bit_cast<float>(std::bit_cast<std::uint32_t>(q) - step_);
  }

  std::uint32_t step_;  // one unit in the format's last place, in fp32 fraction bits
  float min_normal_, max_finite_;
};

// The splice advances its below output by bit 0 and its above output by bit 1.
enum class Side : std::uint8_t { kBoth = 0, kBelow = 1, kAbove = 2 };

// The sweep's blocks: a node's event list is swept in blocks of about this many events
// (each starting at a new position), and lists shorter than two blocks in one.
constexpr std::size_t kSweepBlock = 32;

// The sweep's counts where a block starts (find_split): the block's first event and
// #(lo <= q), #(hi < q) over the events before it.
struct Mark {
  std::uint32_t index = 0, lo_at_or_below = 0, hi_below = 0;
};

struct Split {
  double cost = std::numeric_limits<double>::infinity();
  int axis = -1;
  float pos = 0.0f;
  // The sweep's counts at the plane, which are exactly the children's triangle counts.
  std::uint32_t below = 0, above = 0;
};

// A coordinate as the units load it: rounded to nearest even into the format, with
// subnormals flushed (docs/numbers.md, from_fp32). fp32 needs only the flush.
float round_into(fp::Format f, float x) {
  if (f == fp::kFp32) return std::fpclassify(x) == FP_SUBNORMAL ? 0.0f * x : x;
  return as_float(f, fp::soft::from_fp32(f, std::bit_cast<std::uint32_t>(x)));
}

class Builder {
 public:
  Builder(const Scene& scene, const KdBuildConfig& config, KdTree& tree)
      : scene_(scene), config_(config), tree_(tree), grid_(config.format), sides_(scene.triangles.size()),
        straddlers_(scene.triangles.size() + 1) {
    // No list is longer than two events per triangle, so the marks never reallocate.
    for (std::vector<Mark>& marks : marks_) marks.reserve(2 * scene.triangles.size() / kSweepBlock + 1);
    round_vertices();
  }

  // The root box: the box of the rounded vertices, whose coordinates are grid values.
  Bounds32 root() const { return root_; }

  void run() {
    const std::size_t n = scene_.triangles.size();
    triangles_.resize(n);
    levels_.resize(static_cast<std::size_t>(config_.max_depth) + 1);
    EventLists& events = levels_[0].below;
    for (EventLists::value_type& list : events) list.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      Triangle& t = triangles_[i];
      for (int v = 0; v < 3; ++v) t.vertices[v] = positions_[scene_.triangles[i][v]];
      Extent e;
      for (int k = 0; k < 3; ++k) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int v = 0; v < 3; ++v) {
          const double x = t.vertices[v][k];
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
        e.lo[k] = grid_.down(round_down(lo - margin_));
        e.hi[k] = grid_.up(round_up(hi + margin_));
      }
      t.bounds = intersect(e, root_);
      add_events(events, t.bounds, static_cast<std::uint32_t>(i));
    }
    std::vector<glm::vec3>().swap(positions_);  // the records hold what the build needs
    // W&H: the one sort; every node below keeps the order by splicing.
    for (EventLists::value_type& list : events) sort_events(list, sort_scratch_);
    if (must_be_leaf(n, 0)) {
      make_leaf(new_node(), events[0], Side::kBoth);
    } else {
      build(events, root_, n, 0);
    }
  }

 private:
  // Moves every vertex into kd space, rounds it into the format and derives the margin
  // and the root box. Kd-space magnitudes lie inside the format's range. The
  // margin is margin_ulps ulps of the format at the largest coordinate magnitude, the
  // scale of the units' rounding errors (docs/kdtree.md, "The margin").
  void round_vertices() {
    const fp::Format f = config_.format;
    tree_.scale_exponent = kd_scale_exponent(scene_, f);
    positions_.resize(scene_.positions.size());
    for (std::size_t i = 0; i < positions_.size(); ++i) {
      const glm::vec3 kd = to_kd_space(scene_.positions[i], tree_.scale_exponent);
      for (int k = 0; k < 3; ++k) positions_[i][k] = round_into(f, kd[k]);
    }
    for (int k = 0; k < 3; ++k) {
      root_.lo[k] = kInf;
      root_.hi[k] = -kInf;
    }
    float magnitude = 0.0f;
    for (const glm::uvec3& t : scene_.triangles) {
      for (int v = 0; v < 3; ++v) {
        for (int k = 0; k < 3; ++k) {
          const float x = positions_[t[v]][k];
          if (!std::isfinite(scene_.positions[t[v]][k])) {
            throw Error(fmt::format("scene '{}': vertex {} coordinate {} is not finite; fix the geometry",
                                    scene_.source, t[v], scene_.positions[t[v]][k]));
          }
          root_.lo[k] = std::min(root_.lo[k], x);
          root_.hi[k] = std::max(root_.hi[k], x);
          magnitude = std::max(magnitude, std::abs(x));
        }
      }
    }
    const int exponent = magnitude == 0.0f ? f.min_exponent() : std::max(std::ilogb(magnitude), f.min_exponent());
    margin_ = config_.margin_ulps * std::ldexp(1.0, exponent - f.fraction_bits);
    if (!(double(magnitude) + margin_ <= grid_.max_finite())) {
      throw Error(fmt::format("scene '{}': coordinates up to {} plus the kd-tree margin of {} ulps exceed the "
                              "range of number format {}; lower the margin or choose a wider format",
                              scene_.source, magnitude, config_.margin_ulps, f.name()));
    }
  }

  // W&H: sweep each axis's sorted events. At a position q holding pe ends, pp
  // planar and ps starts, with A = #(lo < q) and B = #(hi < q) seen so far, a plane
  // at grid value c references #(lo <= c) triangles below and #(hi >= c) above (the
  // conservative rule). Rather than at q itself, where both the planar triangles and
  // the ones ending or starting at q would go to both sides, the sweep tries planes
  // one grid step off q: c = next_down(q) puts the planar and starting triangles above
  // only, c = next_up(q) puts the planar and ending ones below only. Choosing the
  // cheaper is W&H's planar side rule moved off the plane by one ulp of the format.
  // When a neighbouring position is exactly that ulp away, q itself is the plane
  // between them and is tried instead.
  //
  // Between two neighbouring positions q < q' every plane has the same counts (below:
  // A + ps + pp at q, above: N - B - pe - pp), so the score, linear in c with slope
  // side * (below - above), is smallest at one end of the gap: next_up(q) when below
  // >= above (on a tie the lower plane, as a sweep trying both in order keeps it),
  // next_down(q') otherwise. Only that end is costed. Event positions lie in the
  // node's box, so only the gaps below the first and above the last position can
  // reach beyond it.
  //
  // Most gaps of a large node cannot win, and the sweep skips them in blocks (a
  // branch-and-bound on W&H's sweep). A counting pass records the counts at every
  // block boundary and the score of the plane the sweep would cost in the gap there;
  // the smallest of these bounds the winner's score from above. A block's candidates
  // lie between its first position and the next block's, with at least the counts at
  // its start below and at its end above, and the score, computed in correctly
  // rounded double from non-negative terms, is monotone in each; so a block whose
  // score at those extremes exceeds the bound or the best so far holds no winner and
  // is skipped. Every candidate the full sweep could pick is still costed in the same
  // order and arithmetic, so the tree is the same.
  Split find_split(const EventLists& events, const Bounds32& box, std::size_t n) {
    // The sweep minimises bonus * (A_below * N_below + A_above * N_above) with A half a
    // child's surface area; the cost formula is applied to the winner only.
    double best_score = std::numeric_limits<double>::infinity();
    Split best;
    const double keep = 1.0 - config_.empty_bonus;
    const std::uint32_t total = static_cast<std::uint32_t>(n);
    // Counts: #(lo <= q) and #(hi < q), one compare each per event on its code
    // (kind << 30 | triangle): a start or planar event has lo at its position, an
    // end or planar event hi.
    constexpr std::uint32_t kPlanarCode = kPlanar << kTriBits, kStartCode = kStart << kTriBits;
    struct Geometry {
      double cap, side, lo, hi;
      // The score of a plane with `below` and `above` triangles, taking the plane at
      // c_below for the below child's area and at c_above for the above child's; a
      // candidate's score has both at its position.
      double score(float c_below, float c_above, std::uint32_t below, std::uint32_t above) const {
        return (cap + (c_below - lo) * side) * below + (cap + (hi - c_above) * side) * above;
      }
    };
    std::array<Geometry, 3> geometry;
    double bound = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      std::vector<Mark>& marks = marks_[k];
      marks.assign(1, Mark{});
      if (!(box.lo[k] < box.hi[k])) continue;  // a flat node cannot be cut on this axis
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const double da = double(box.hi[a]) - box.lo[a], db = double(box.hi[b]) - box.lo[b];
      const Geometry& g = geometry[k] = {da * db, da + db, box.lo[k], box.hi[k]};
      // The counting pass, for lists long enough to have blocks to skip.
      const EventList& ev = events[k];
      const std::size_t size = ev.size();
      std::uint32_t lo_at_or_below = 0, hi_below = 0;
      std::size_t i = 0;
      for (std::size_t next = kSweepBlock; size >= 2 * kSweepBlock && next < size; next = i + kSweepBlock) {
        for (; next < size && ev[next].pos == ev[next - 1].pos; ++next) {}  // blocks start at a position
        // In local sums over a plain range, which the compiler vectorises.
        std::uint32_t lo_sum = 0, hi_sum = 0;
        for (const Event *e = ev.data() + i, *const last = ev.data() + next; e != last; ++e) {
          lo_sum += e->code >= kPlanarCode;
          hi_sum += e->code < kStartCode;
        }
        lo_at_or_below += lo_sum;
        hi_below += hi_sum;
        i = next;
        if (i == size) break;
        marks.push_back({static_cast<std::uint32_t>(i), lo_at_or_below, hi_below});
        // The gap between ev[i - 1] and ev[i] is an inner one; its plane when the two
        // are not adjacent on the grid, as the sweep below chooses it.
        const std::uint32_t below = lo_at_or_below, above = total - hi_below;
        const float up = grid_.next_up(ev[i - 1].pos);
        if (up != ev[i].pos) {
          const float c = below >= above ? up : grid_.next_down(ev[i].pos);
          bound = std::min(bound, g.score(c, c, below, above));
        }
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (!(box.lo[k] < box.hi[k])) continue;
      const Geometry& g = geometry[k];
      const auto inside = [&](float c) { return box.lo[k] < c && c < box.hi[k]; };
      const auto consider = [&](double score, float c, std::uint32_t below, std::uint32_t above) {
        if (score < best_score) {
          best_score = score;
          best.axis = k;
          best.pos = c == 0.0f ? 0.0f : c;
          best.below = below;
          best.above = above;
        }
      };
      // Planes between the first and the last position have triangles on both sides,
      // so the empty bonus (a factor 1 there, which is exact) is only applied outside.
      const auto try_plane = [&](float c, std::uint32_t below, std::uint32_t above) {
        consider(g.score(c, c, below, above), c, below, above);
      };
      const auto try_outer_plane = [&](float c, std::uint32_t below, std::uint32_t above) {
        consider(g.score(c, c, below, above) * (below == 0 || above == 0 ? keep : 1.0), c, below, above);
      };
      const EventList& ev = events[k];
      const Event* const end = ev.data() + ev.size();
      if (const float down = grid_.next_down(ev.front().pos); inside(down)) {
        try_outer_plane(down, 0, total);  // below the first position
      }
      // Sweeps the positions from `e` (the first of its position) to `stop` (likewise,
      // or the end), with the counts before e. `next_up` and `next_down` give the grid
      // neighbours of the positions between the first and the last; the outer planes
      // use the grid's.
      const auto sweep = [&](auto next_up, auto next_down, const Event* e, const Event* stop,
                             std::uint32_t lo_at_or_below, std::uint32_t hi_below) {
        // Whether the previous position is one grid step below q.
        bool adjacent_below = e != ev.data() && next_up(e[-1].pos) == e->pos;
        for (;;) {
          const float q = e->pos;
          const std::uint32_t above_q = total - hi_below;  // the plane at q: #(hi >= q)
          do {
            lo_at_or_below += e->code >= kPlanarCode;
            hi_below += e->code < kStartCode;
            ++e;
          } while (e != end && e->pos == q);
          // The gap above q: below #(lo <= q), above #(hi > q).
          const std::uint32_t below = lo_at_or_below, above = total - hi_below;
          if (e == end) {
            // The last gap has only its lower end, which may lie on the box.
            if (const float up = grid_.next_up(q); up < box.hi[k]) try_outer_plane(up, below, above);
            if (adjacent_below) try_plane(q, below, above_q);
            return;
          }
          // Both ends of an inner gap lie strictly inside the box. The cheaper end is
          // costed (both on an exact tie of the counts, so that the rounding of the two
          // scores decides as in a sweep that costs every candidate: the tree is
          // bit-identical to that sweep's, checked with kdtree_table --hash).
          const float up = next_up(q);
          const bool adjacent_above = up == e->pos;
          if (!adjacent_above) {
            if (below >= above) try_plane(up, below, above);
            if (below <= above) try_plane(next_down(e->pos), below, above);
          }
          if (adjacent_below || adjacent_above) try_plane(q, below, above_q);
          if (e == stop) return;
          adjacent_below = adjacent_above;
        }
      };
      const auto sweep_blocks = [&](auto next_up, auto next_down) {
        const std::vector<Mark>& marks = marks_[k];
        for (std::size_t m = 0; m < marks.size(); ++m) {
          const Event* const first = ev.data() + marks[m].index;
          const Event* stop = end;
          if (m + 1 < marks.size()) {
            stop = ev.data() + marks[m + 1].index;
            const double least = g.score(first->pos, stop->pos, marks[m].lo_at_or_below, total - marks[m + 1].hi_below);
            if (least > std::min(bound, best_score)) continue;
          }
          sweep(next_up, next_down, first, stop, marks[m].lo_at_or_below, marks[m].hi_below);
        }
      };
      if (box.lo[k] > 0.0f || box.hi[k] < 0.0f) {
        // In a box that does not contain zero, the positions other than the last are
        // normal numbers of one sign whose grid neighbours are one step of the fp32
        // bits away (the bits of a negative float grow with its magnitude).
        const std::uint32_t step = box.lo[k] > 0.0f ? grid_.step() : 0u - grid_.step();
        sweep_blocks([step](float q) { return std::bit_cast<float>(std::bit_cast<std::uint32_t>(q) + step); },
                     [step](float q) { return std::bit_cast<float>(std::bit_cast<std::uint32_t>(q) - step); });
      } else {
        sweep_blocks([this](float q) { return grid_.next_up(q); }, [this](float q) { return grid_.next_down(q); });
      }
    }
    if (best.axis >= 0) {
      best.cost = config_.traversal_cost + config_.intersection_cost * 2.0 * best_score / surface_area(box);
    }
    return best;
  }

  // W&H: a triangle goes below when its extent starts at or before the plane and
  // above when it ends at or after it; touching counts (the closed-box rule). One pass
  // over the sorted list suffices because a triangle's start event comes before its end
  // event. The pass is split where the positions cross the plane, so that within each
  // part the side follows from the event kind without a branch on it (the kinds come
  // in random order; the positions do not). Writes the triangles on both sides to
  // straddlers_ and returns how many there are.
  std::size_t classify(const EventList& ev, float split) {
    const Event* e = ev.data();
    const Event* const end = e + ev.size();
    std::uint32_t* const first = straddlers_.data();
    std::uint32_t* out = first;
    // Before the plane: a start leaves the triangle on both sides until its end (if
    // any) before the plane makes it below.
    for (; e != end && e->pos < split; ++e) sides_[e->tri()] = e->kind() == kStart ? Side::kBoth : Side::kBelow;
    // On the plane: every triangle touches it. Planar ones and those ending here are
    // complete; the ones starting here end above.
    for (; e != end && e->pos == split; ++e) {
      sides_[e->tri()] = Side::kBoth;
      *out = e->tri();
      out += e->kind() != kStart;
    }
    // Above the plane: starts and planar events are above; an end closes a triangle
    // that started at or before the plane, which is then on both sides.
    // In masks, so that the compiler does not branch on the kind.
    for (; e != end; ++e) {
      const std::uint32_t t = e->tri();
      const auto side = static_cast<unsigned>(sides_[t]);
      const unsigned is_end = e->kind() == kEnd, keep = 0u - is_end;
      *out = t;
      out += is_end & static_cast<unsigned>(side == static_cast<unsigned>(Side::kBoth));
      sides_[t] = static_cast<Side>((side & keep) | (static_cast<unsigned>(Side::kAbove) & ~keep));
    }
    return static_cast<std::size_t>(out - first);
  }

  // The extent of a triangle that straddles a plane, inside one child's box: its
  // widened bounding box clipped to the child, or with perfect_splits the bounds of the
  // part of the (rounded) triangle within the margin of the child, widened by the
  // margin (W&H's "perfect splits"; Sutherland-Hodgman in double against the child box
  // grown by the margin).
  Extent child_extent(std::uint32_t tri, const Bounds32& box) const {
    const Triangle& t = triangles_[tri];
    const Extent loose = intersect(t.bounds, box);
    if (!config_.perfect_splits) return loose;
    // Computed vertices carry double rounding error relative to `scale`; they are widened
    // by far less than an fp32 ulp more than the rounded input vertices, so that the
    // extent stays conservative.
    double scale = 0.0;
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs(double(t.vertices[v][k])));
    }
    for (int k = 0; k < 3; ++k) scale = std::max({scale, std::abs(double(box.lo[k])), std::abs(double(box.hi[k]))});
    const double exact_widening = margin_, clipped_widening = margin_ + scale * 0x1p-40;
    struct Vertex {
      glm::dvec3 p;
      double widening;
    };
    std::array<Vertex, 9> buffers[2];
    Vertex* poly = buffers[0].data();
    Vertex* clipped = buffers[1].data();
    std::size_t count = 3;
    for (int v = 0; v < 3; ++v) poly[v] = {glm::dvec3(t.vertices[v]), exact_widening};
    for (int plane = 0; plane < 6 && count > 0; ++plane) {
      const int k = plane / 2;
      const double at = plane % 2 == 0 ? box.lo[k] - margin_ : box.hi[k] + margin_;
      const double sign = plane % 2 == 0 ? 1.0 : -1.0;  // inside: sign * (x - at) >= 0
      // Most planes leave the polygon whole (the widened bounds already lie inside).
      if ((plane % 2 == 0 ? t.bounds.lo[k] >= box.lo[k] : t.bounds.hi[k] <= box.hi[k])) continue;
      std::size_t out = 0;
      for (std::size_t v = 0; v < count; ++v) {
        const Vertex& cur = poly[v];
        const Vertex& nxt = poly[v + 1 == count ? 0 : v + 1];
        const double dc = sign * (cur.p[k] - at), dn = sign * (nxt.p[k] - at);
        if (dc >= 0.0) clipped[out++] = cur;
        if ((dc >= 0.0) != (dn >= 0.0)) {
          Vertex x{cur.p + (dc / (dc - dn)) * (nxt.p - cur.p), clipped_widening};
          x.p[k] = at;
          clipped[out++] = x;
        }
      }
      count = out;
      std::swap(poly, clipped);
    }
    if (count == 0) return loose;  // only a touch the clipping rounded away
    Extent tight;
    for (int k = 0; k < 3; ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::size_t v = 0; v < count; ++v) {
        lo = std::min(lo, poly[v].p[k] - poly[v].widening);
        hi = std::max(hi, poly[v].p[k] + poly[v].widening);
      }
      tight.lo[k] = grid_.down(round_down(lo));
      tight.hi[k] = grid_.up(round_up(hi));
    }
    return intersect(tight, loose);
  }

  // One pass over a parent list: each one-sided event is merged with that side's new
  // (sorted) straddler events straight into the child list, so every event is written
  // once. The sides come in random order, so rather than branch on them the pass
  // writes each event to both outputs and advances the one that keeps it: an output
  // keeps its side's events unless its child becomes a leaf and needs none (it then
  // points at one event that is overwritten), and has room for one event more than it
  // keeps. A new event is written before the first parent event it precedes, of
  // either side, since the ones of its own side come after that one too.
  std::pair<Event*, Event*> splice(const EventList& parent, const EventList& new_below,
                                   const EventList& new_above, Event* below, Event* above,
                                   bool keep_below, bool keep_above) const {
    const Event *nb = new_below.data(), *const nb_end = nb + new_below.size();
    const Event *na = new_above.data(), *const na_end = na + new_above.size();
    const auto first_new = [&] {  // no new event lies below this position
      return std::min(nb != nb_end ? nb->pos : kInf, na != na_end ? na->pos : kInf);
    };
    float next_new = first_new();
    const unsigned below_bit = keep_below ? 1u : 0u, above_bit = keep_above ? 2u : 0u;
    const auto keep = [&](const Event& e) {
      const auto s = static_cast<unsigned>(sides_[e.tri()]);
      *below = e;
      below += s & below_bit;
      *above = e;
      above += (s & above_bit) >> 1;
    };
    // Runs of parent events that all lie below the next new position need no merge
    // check (the positions are sorted, so the run's last one tells).
    constexpr std::ptrdiff_t kRun = 16;
    const Event* e = parent.data();
    const Event* const end = e + parent.size();
    while (e != end) {
      if (end - e >= kRun && e[kRun - 1].pos < next_new) {
        for (const Event* const run_end = e + kRun; e != run_end; ++e) keep(*e);
        continue;
      }
      if (e->pos >= next_new) {  // rare: new events may come first
        for (; nb != nb_end && *nb < *e; ++nb) *below++ = *nb;
        for (; na != na_end && *na < *e; ++na) *above++ = *na;
        next_new = first_new();
      }
      keep(*e++);
    }
    return {std::copy(nb, nb_end, below), std::copy(na, na_end, above)};
  }

  bool must_be_leaf(std::size_t n, int depth) const {
    return n <= config_.max_leaf_prims || depth >= config_.max_depth;
  }

  // Appends a leaf's triangles to `out`: one start or planar event per triangle in any
  // axis list, of those on side `side` or both (kBoth: all).
  void append_triangles(const EventList& ev, Side side, std::vector<std::uint32_t>& out) const {
    const Side other = side == Side::kBelow ? Side::kAbove : Side::kBelow;
    for (const Event& e : ev) {
      if (e.kind() != kEnd && (side == Side::kBoth || sides_[e.tri()] != other)) out.push_back(e.tri());
    }
  }

  // Makes node `index` the leaf of the references from `first` on.
  void make_leaf(std::uint32_t index, std::size_t first) {
    const std::size_t count = tree_.prim_refs.size() - first;
    if (count > KdNode::kMaxIndex || tree_.prim_refs.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw Error(fmt::format("kd-tree for '{}' needs more primitive references than the kd-node "
                              "fields hold; raise max_leaf_prims or lower max_depth",
                              scene_.source));
    }
    tree_.nodes[index] = KdNode::leaf(static_cast<std::uint32_t>(count), static_cast<std::uint32_t>(first));
  }

  void make_leaf(std::uint32_t index, const EventList& ev, Side side) {
    const std::size_t first = tree_.prim_refs.size();
    append_triangles(ev, side, tree_.prim_refs);
    make_leaf(index, first);
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

  // A consumed list keeps its storage for the next node at its depth, unless it is
  // large: the few large nodes allocate afresh, and what the pool holds stays small.
  static void recycle(EventList& list) {
    constexpr std::size_t kKeptEvents = 4096;
    if (list.capacity() > kKeptEvents) {
      EventList().swap(list);
    } else {
      list.clear();
    }
  }

  // Builds the subtree of a node that may be split; `events` are its sorted lists,
  // which it consumes.
  void build(EventLists& events, const Bounds32& box, std::size_t n, int depth) {
    const std::uint32_t index = new_node();
    const Split split = find_split(events, box, n);
    // W&H's automatic termination: split only when it is cheaper than intersecting all n.
    if (split.axis < 0 || split.cost >= config_.intersection_cost * static_cast<double>(n)) {
      make_leaf(index, events[0], Side::kBoth);
      for (EventList& list : events) recycle(list);
      return;
    }
    const int k = split.axis;
    const std::size_t n_below = split.below, n_above = split.above;
    const std::size_t n_straddlers = classify(events[k], split.pos);

    Bounds32 below_box = box, above_box = box;
    below_box.hi[k] = split.pos;
    above_box.lo[k] = split.pos;

    // A child that will be a leaf needs only its triangles, not events. The below one
    // is the next node; the above one's references wait until the below subtree is done.
    const bool below_leaf = must_be_leaf(n_below, depth + 1), above_leaf = must_be_leaf(n_above, depth + 1);
    Level& children = levels_[static_cast<std::size_t>(depth) + 1];
    if (below_leaf) make_leaf(new_node(), events[k], Side::kBelow);
    if (above_leaf) {
      children.above_leaf.clear();
      append_triangles(events[k], Side::kAbove, children.above_leaf);
    }

    if (!below_leaf || !above_leaf) {
      // W&H: triangles on one side keep their events, in order; straddlers get new
      // events for each child, sorted on their own (few) and merged in. Generated in
      // triangle order, as sort_events needs.
      EventLists& new_below = new_below_;
      EventLists& new_above = new_above_;
      for (int axis = 0; axis < 3; ++axis) {
        new_below[axis].clear();
        new_above[axis].clear();
      }
      std::sort(straddlers_.begin(), straddlers_.begin() + static_cast<std::ptrdiff_t>(n_straddlers));
      for (std::size_t i = 0; i < n_straddlers; ++i) {
        // The records are read in index order but far apart: fetch a few ahead.
        constexpr std::size_t kPrefetch = 8;
        if (i + kPrefetch < n_straddlers) __builtin_prefetch(&triangles_[straddlers_[i + kPrefetch]]);
        const std::uint32_t t = straddlers_[i];
        if (!below_leaf) add_events(new_below, child_extent(t, below_box), t);
        if (!above_leaf) add_events(new_above, child_extent(t, above_box), t);
      }
      for (int axis = 0; axis < 3; ++axis) {
        sort_events(new_below[axis], sort_scratch_);
        sort_events(new_above[axis], sort_scratch_);
        // At most two events per one-sided triangle, and one slot the splice may write
        // without keeping; the lists are cut to size after the splice, which saves a
        // counting pass over the parent list.
        EventList& below = children.below[axis];
        EventList& above = children.above[axis];
        Event sink;  // the output of a leaf child
        if (!below_leaf) below.resize(2 * (n_below - n_straddlers) + new_below[axis].size() + 1);
        if (!above_leaf) above.resize(2 * (n_above - n_straddlers) + new_above[axis].size() + 1);
        const auto [end_below, end_above] =
            splice(events[axis], new_below[axis], new_above[axis], below_leaf ? &sink : below.data(),
                   above_leaf ? &sink : above.data(), !below_leaf, !above_leaf);
        if (!below_leaf) below.resize(static_cast<std::size_t>(end_below - below.data()));
        if (!above_leaf) above.resize(static_cast<std::size_t>(end_above - above.data()));
      }
    }
    for (EventList& list : events) recycle(list);

    if (!below_leaf) build(children.below, below_box, n_below, depth + 1);
    const std::uint32_t above_index = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes[index] = KdNode::inner(k, above_index, split.pos);
    if (above_leaf) {
      const std::size_t first = tree_.prim_refs.size();
      tree_.prim_refs.insert(tree_.prim_refs.end(), children.above_leaf.begin(), children.above_leaf.end());
      make_leaf(new_node(), first);
    } else {
      build(children.above, above_box, n_above, depth + 1);
    }
  }

  // Scratch of one depth of the tree, reused by every node there: the event lists of
  // the two children of the node being split at the depth above (the build is depth
  // first, so both are consumed before the next node there is split), and the
  // references of an above child that is a leaf.
  struct Level {
    EventLists below, above;
    std::vector<std::uint32_t> above_leaf;
  };

  const Scene& scene_;
  const KdBuildConfig& config_;
  KdTree& tree_;
  Grid grid_;
  std::vector<Side> sides_;
  std::array<std::vector<Mark>, 3> marks_;  // find_split's blocks, per axis
  // classify's output: one slot per triangle and one that the branch-free pass may
  // write without keeping.
  std::vector<std::uint32_t> straddlers_;
  EventList sort_scratch_;
  std::vector<Level> levels_;           // one per depth
  EventLists new_below_, new_above_;   // the straddlers' events in the node being split
  std::vector<glm::vec3> positions_;  // the scene's vertices rounded into the format
  double margin_ = 0.0;               // added around every triangle, in scene units
  Bounds32 root_;
  // What clipping a triangle reads, in one cache line: the build visits triangles in no
  // spatial order, and separate arrays of vertices and bounds cost a cache miss each.
  struct alignas(64) Triangle {
    std::array<glm::vec3, 3> vertices;  // rounded into the format
    Extent bounds;                      // widened bounding box on the grid, within the root
  };
  std::vector<Triangle> triangles_;
};

void check_config(const Scene& scene, const KdBuildConfig& c) {
  if (c.max_depth > c.stack_depth) {
    throw Error(fmt::format("kd-tree max depth {} exceeds the traversal stack depth {} of config "
                            "'{}'; lower --kd-depth or choose a config with a deeper stack",
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
  const fp::Format f = c.format;
  if (f.exponent_bits < 2 || f.exponent_bits > 8 || f.fraction_bits < 1 || f.fraction_bits > 23) {
    throw Error(fmt::format("kd-tree number format E{}M{} is not one the units compute in; choose a format "
                            "with 2 <= E <= 8 and 1 <= M <= 23 (docs/numbers.md)",
                            f.exponent_bits, f.fraction_bits));
  }
  if (c.margin_ulps < 0 || c.margin_ulps > kKdMaxMarginUlps) {
    throw Error(fmt::format("kd-tree margin of {} ulps is outside [0, {}]; choose a margin in that range",
                            c.margin_ulps, kKdMaxMarginUlps));
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
  s.scale_exponent = tree.scale_exponent;
  struct Item {
    std::uint32_t index;
    Bounds32 box;
    int depth;
  };
  Bounds32 root;
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

float largest_coordinate(const Scene& scene) {
  float magnitude = 0.0f;
  for (const glm::uvec3& t : scene.triangles) {
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) {
        const float x = std::abs(scene.positions[t[v]][k]);
        if (x < std::numeric_limits<float>::infinity()) magnitude = std::max(magnitude, x);  // not NaN or inf
      }
    }
  }
  return magnitude;
}

int kd_scale_exponent(const Scene& scene, fp::Format format) {
  const float magnitude = largest_coordinate(scene);
  // Zero and subnormal magnitudes read as zero (docs/numbers.md): nothing to scale.
  if (!(magnitude >= std::numeric_limits<float>::min())) return 0;
  const int target = std::min(kKdMagnitudeExponent, format.max_exponent() / 2);
  return std::max(std::ilogb(magnitude) - target, kKdMinScaleExponent);
}

KdTree build_kdtree(const Scene& scene, const KdBuildConfig& config) {
  check_config(scene, config);
  const auto start = std::chrono::steady_clock::now();
  KdTree tree;
  tree.format = config.format;
  Builder builder(scene, config, tree);
  const Bounds32 root = builder.root();
  tree.bounds_lo = glm::vec3(root.lo[0], root.lo[1], root.lo[2]);
  tree.bounds_hi = glm::vec3(root.hi[0], root.hi[1], root.hi[2]);
  builder.run();
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
      "kd space         world x 2^{}\n"
      "build time       {:.3f} s\n",
      s.nodes, inner, s.leaves, s.empty_leaves, s.max_depth, s.mean_leaf_depth, s.mean_prims_per_leaf,
      s.prim_refs, s.sah_cost, s.bytes, static_cast<double>(s.bytes) / (1024.0 * 1024.0), -s.scale_exponent,
      s.build_seconds);
}

std::string lost_planes_note(const std::string& format_name, const KdTreeStats& tree, const KdTreeStats& fp32_tree) {
  if (!(tree.sah_cost > kLostPlanesRatio * fp32_tree.sah_cost)) return {};
  return fmt::format(
      "{} cannot place the planes this scene needs: its tree has {} nodes, {:.1f} triangles a non-empty leaf and "
      "SAH cost {:.1f}, against fp32's {} nodes, {:.1f} and {:.1f}; its planes lie on the format's grid and each "
      "triangle is widened by its rounding margin, coarser here than the triangles: the SAH's expected work "
      "of a ray is {:.1f} times fp32's (docs/kdtree.md \"Conservative splits in any format\")",
      format_name, tree.nodes, tree.mean_prims_per_leaf, tree.sah_cost, fp32_tree.nodes, fp32_tree.mean_prims_per_leaf,
      fp32_tree.sah_cost, tree.sah_cost / fp32_tree.sah_cost);
}

}  // namespace rpu
