#include "functional/tracer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "common/error.hpp"
#include "fp/fast32.hpp"
#include "functional/arith.hpp"
#include "functional/intersection_unit.hpp"
#include "kdtree/kd_node.hpp"
#include "rpu/spec.hpp"

namespace rpu::functional {

namespace {
static_assert(std::endian::native == std::endian::little, "the memory image is read in place as little-endian");


std::uint32_t read_u32(std::span<const std::uint8_t> image, std::uint32_t offset) {
  std::uint32_t v;
  std::memcpy(&v, image.data() + offset, sizeof v);
  return v;
}

template <class V>
struct StackEntry {
  std::uint32_t node;
  V t_near, t_far;
};

// The largest stack a configuration may ask for; kd trees are at most this deep.
constexpr int kMaxStackDepth = 64;

// §2 Clip to the scene box. The near and far plane of each axis are chosen by the
// sign of 1/d (so +0 and -0 pick opposite planes); a NaN from 0 * inf (origin on a
// plane, direction parallel to it) never narrows the interval. False: the ray misses
// the box.
template <class Arith>
[[gnu::always_inline]] inline bool clip_to_scene(const Arith& ar, const RayRegisters<Arith>& ray, const ImageLayout& layout,
                   typename Arith::Value& t_near, typename Arith::Value& t_far) {
  using V = typename Arith::Value;
  t_near = ray.t_min;
  t_far = ray.t_max;
  const float lo[3] = {layout.bounds_lo.x, layout.bounds_lo.y, layout.bounds_lo.z};
  const float hi[3] = {layout.bounds_hi.x, layout.bounds_hi.y, layout.bounds_hi.z};
  for (int i = 0; i < 3; ++i) {
    const V t_lo = ar.mul(ar.sub(ar.load(std::bit_cast<std::uint32_t>(lo[i])), ray.origin[i]), ray.inv_direction[i]);
    const V t_hi = ar.mul(ar.sub(ar.load(std::bit_cast<std::uint32_t>(hi[i])), ray.origin[i]), ray.inv_direction[i]);
    const bool negative = ar.sign(ray.inv_direction[i]);
    const V entry = negative ? t_hi : t_lo;
    const V exit = negative ? t_lo : t_hi;
    if (ar.gt(entry, t_near)) t_near = entry;
    if (ar.lt(exit, t_far)) t_far = exit;
  }
  return ar.le(t_near, t_far);
}

// One ray's step at an inner node: which child it visits first, and whether it needs
// only that one, only the other, or both (then the other is pushed with [t_split, t_far]).
template <class V>
struct InnerStep {
  enum class Needs : std::uint8_t { kFirst, kSecond, kBoth } needs;
  std::uint32_t first, second;
  V t_split;
};

template <class Arith>
[[gnu::always_inline]] inline InnerStep<typename Arith::Value> inner_step(const Arith& ar, const RayRegisters<Arith>& ray, const KdNode& node,
                                            std::uint32_t node_index, typename Arith::Value t_near,
                                            typename Arith::Value t_far) {
  using V = typename Arith::Value;
  using Needs = typename InnerStep<V>::Needs;
  const int axis = node.split_axis();
  const V split = ar.load(node.split_bits());
  const V t_split = ar.mul(ar.sub(split, ray.origin[axis]), ray.inv_direction[axis]);
  const bool below_first = ar.lt(ray.origin[axis], split) ||
                           (ar.eq(ray.origin[axis], split) && ar.le(ray.direction[axis], ar.zero()));
  const std::uint32_t first = below_first ? node_index + 1 : node.above_child();
  const std::uint32_t second = below_first ? node.above_child() : node_index + 1;
  // The plane behind, beyond, or (NaN) the ray lying in it: only the first child.
  const Needs needs = !ar.le(t_split, t_far) || ar.le(t_split, ar.zero()) ? Needs::kFirst
                      : ar.lt(t_split, t_near)                           ? Needs::kSecond
                                                                         : Needs::kBoth;
  return {needs, first, second, t_split};
}

std::string stack_overflow(std::uint32_t node_index, int stack_depth) {
  return fmt::format(
      "traversal stack overflow at kd node {} (stack depth {}): the image's tree is deeper than the traversal "
      "unit's stack; rebuild it with a max depth <= {}",
      node_index, stack_depth, stack_depth);
}

// What trace_with reports of the walk: nothing on the plain path, the events with a log.
// test() sees each IU test with its inputs and result.
struct NoRecorder {
  void operator()(TraceEvent::Kind, std::uint32_t) const {}
  template <class Arith, class V>
  void test(const RayRegisters<Arith>&, const IsectRecord&, V, bool,
            const UnitHit<Arith>&) const {}
};
struct LogRecorder : NoRecorder {
  TraceLog& log;
  explicit LogRecorder(TraceLog& l) : log(l) {}
  void operator()(TraceEvent::Kind kind, std::uint32_t address) const { log.events.push_back({kind, address}); }
};
struct IuRecorder : NoRecorder {
  std::vector<IuTest>& tests;
  explicit IuRecorder(std::vector<IuTest>& t) : tests(t) {}
  void test(const RayRegisters<SoftArith>& ray, const IsectRecord& record,
            std::uint32_t t_best, bool found, const UnitHit<SoftArith>& hit) const {
    tests.push_back({ray, record, t_best, found, found ? hit : UnitHit<SoftArith>{0, 0, 0}});
  }
};
}  // namespace

Tracer::Tracer(std::span<const std::uint8_t> image, const ImageLayout& layout, fp::Format format, int stack_depth,
               bool fast_path)
    : image_(image),
      layout_(layout),
      format_(format),
      stack_depth_(stack_depth),
      record_bytes_(isect_record_bytes(layout.isect_mode)),
      fast_(fast_path && format == fp::kFp32) {
  if (stack_depth < 1 || stack_depth > kMaxStackDepth) {
    throw Error(fmt::format("traversal stack depth {} is outside 1..{}", stack_depth, kMaxStackDepth));
  }
}

TraceHit Tracer::trace(const TraceRay& ray, TraceMode mode) const {
  NoRecorder none;
  if (fast_) {
    const fp::fast32::FlushScope flush;
    return trace_with(Fast32Arith{}, ray, mode, none);
  }
  return trace_with(SoftArith{format_}, ray, mode, none);
}

TraceHit Tracer::trace(const TraceRay& ray, TraceMode mode, TraceLog& log) const {
  log.events.clear();
  log.mode = mode;
  LogRecorder recorder{log};
  if (fast_) {
    const fp::fast32::FlushScope flush;
    return trace_with(Fast32Arith{}, ray, mode, recorder);
  }
  return trace_with(SoftArith{format_}, ray, mode, recorder);
}

TraceHit Tracer::trace(const TraceRay& ray, TraceMode mode, std::vector<IuTest>& tests) const {
  tests.clear();
  IuRecorder recorder{tests};
  return trace_with(SoftArith{format_}, ray, mode, recorder);
}

void Tracer::trace(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out) const {
  NoRecorder none;
  if (fast_) {
    const fp::fast32::FlushScope flush;
    const Fast32Arith ar;
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = trace_with(ar, rays[i], mode, none);
    return;
  }
  const SoftArith ar{format_};
  for (std::size_t i = 0; i < rays.size(); ++i) out[i] = trace_with(ar, rays[i], mode, none);
}

template <class Arith, class Recorder>
TraceHit Tracer::trace_with(const Arith& ar, const TraceRay& in, TraceMode mode, Recorder& record) const {
  using V = typename Arith::Value;
  TraceHit result;

  // §1 Ray set-up (intersection_unit.hpp).
  const bool watertight = layout_.isect_mode == IsectMode::kWatertight;
  RayRegisters<Arith> ray;
  const int kd_scale = layout_.kd_scale_exponent;
  if (!setup_ray(ar, in, watertight, kd_scale, ray)) return result;

  // §2 Clip to the scene box.
  V t_near, t_far;
  if (!clip_to_scene(ar, ray, layout_, t_near, t_far)) return result;

  // §3 Traversal.
  std::array<StackEntry<V>, kMaxStackDepth> stack;
  int stack_size = 0;
  V t_best = ray.t_max;
  std::uint32_t node_index = 0;
  const std::uint32_t nodes_base = layout_.kd_nodes.offset;
  while (true) {
    const std::uint32_t node_address = nodes_base + spec::memory::kKdNodeBytes * node_index;
    const KdNode node{read_u32(image_, node_address + spec::memory::kKdNodeWord0At),
                      read_u32(image_, node_address + spec::memory::kKdNodeWord1At)};
    ++result.counters.nodes;
    record(node.is_leaf() ? TraceEvent::Kind::kLeaf : TraceEvent::Kind::kInner, node_address);
    if (!node.is_leaf()) {
      const InnerStep<V> step = inner_step(ar, ray, node, node_index, t_near, t_far);
      if (step.needs == InnerStep<V>::Needs::kFirst) {
        node_index = step.first;
      } else if (step.needs == InnerStep<V>::Needs::kSecond) {
        node_index = step.second;
      } else {
        if (stack_size == stack_depth_) throw Error(stack_overflow(node_index, stack_depth_));
        stack[stack_size++] = {step.second, step.t_split, t_far};
        node_index = step.first;
        t_far = step.t_split;
      }
      continue;
    }

    ++result.counters.leaves;
    const std::uint32_t first_ref = node.first_prim_ref();
    for (std::uint32_t k = 0; k < node.prim_count(); ++k) {
      const std::uint32_t ref_address = layout_.prim_refs.offset + spec::memory::kPrimRefBytes * (first_ref + k);
      const std::uint32_t prim = read_u32(image_, ref_address);
      const std::uint32_t record_address = layout_.isect_records.offset + record_bytes_ * prim;
      record(TraceEvent::Kind::kRef, ref_address);
      record(TraceEvent::Kind::kTest, record_address);
      IsectRecord words{};
      std::memcpy(words.data(), image_.data() + record_address, record_bytes_);
      ++result.counters.tests;
      UnitHit<Arith> hit;
      const bool found = watertight ? intersect_watertight(ar, ray, words, t_best, hit)
                                    : intersect_woop(ar, ray, words, t_best, hit);
      record.test(ray, words, t_best, found, hit);
      if (!found) continue;
      t_best = hit.t;
      result.hit = true;
      result.prim = prim;
      result.t = std::bit_cast<float>(fp::scale_fp32(ar.store(hit.t), kd_scale));  // §6: back to world space
      result.u = std::bit_cast<float>(ar.store(hit.u));
      result.v = std::bit_cast<float>(ar.store(hit.v));
      if (mode == TraceMode::kAny) return result;
    }
    // A hit no farther than this leaf's exit is nearer than anything behind it.
    if (result.hit && ar.le(t_best, t_far)) return result;
    // Pop the next subtree. Entries lie front to back, so once the best hit is nearer
    // than an entry's near end, it is nearer than everything left.
    if (stack_size == 0) return result;
    const StackEntry<V>& entry = stack[--stack_size];
    record(TraceEvent::Kind::kPop, 0);
    if (result.hit && ar.lt(t_best, entry.t_near)) return result;
    node_index = entry.node;
    t_near = entry.t_near;
    t_far = entry.t_far;
  }
}


void Tracer::trace_packets(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                           std::size_t packet_rays, PacketCounters& shared) const {
  if (packet_rays < 1 || packet_rays > kMaxPacketRays) {
    throw Error(fmt::format("a packet holds 1 to {} rays, not {}", kMaxPacketRays, packet_rays));
  }
  if (fast_) {
    const fp::fast32::FlushScope flush;
    packets_with(Fast32Arith{}, rays, mode, out, packet_rays, shared);
    return;
  }
  packets_with(SoftArith{format_}, rays, mode, out, packet_rays, shared);
}

// A packet walks as one ray would, with a mask: at an inner node each active ray takes its
// own step (inner_step); the packet visits the near child (by the packet's direction sign
// on the axis) if any ray goes there, and pushes the far child for the rays that go there
// too. A ray that needs both children pushes the far one as its own walk would (its
// first child is then always the near one: t_split > 0 puts its origin on the near side);
// a ray that needs only the far child defers to the entry and rejoins when it is popped,
// without the pop's test, since its own walk went there directly. After a leaf a ray
// waits for the next entry that holds it; an entry's own rays take its interval and the
// pop's test. So every ray visits its own walk's nodes in its own walk's order and ends
// where it ends. A packet whose stack fills starts its rays again alone, each as trace().
template <class Arith>
void Tracer::packets_with(const Arith& ar, std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                          std::size_t packet_rays, PacketCounters& shared) const {
  using V = typename Arith::Value;
  using Needs = typename InnerStep<V>::Needs;
  const bool watertight = layout_.isect_mode == IsectMode::kWatertight;
  const int kd_scale = layout_.kd_scale_exponent;
  NoRecorder none;

  enum class State : std::uint8_t { kActive, kWaiting, kDone };
  struct Lane {
    RayRegisters<Arith> ray;
    V t_near, t_far, t_best;
    std::size_t index;  // in rays and out
    State state;
  };
  struct Entry {
    std::uint32_t node;
    std::array<V, kMaxPacketRays> t_near, t_far;
    std::uint32_t own = 0;       // rays whose own walk pushed it
    std::uint32_t deferred = 0;  // rays that rejoin here without a pop
  };

  // The rays that enter the tree, grouped by the signs of their directions.
  std::array<std::vector<Lane>, 8> by_signs;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    out[i] = TraceHit{};
    Lane lane;
    if (!setup_ray(ar, rays[i], watertight, kd_scale, lane.ray) ||
        !clip_to_scene(ar, lane.ray, layout_, lane.t_near, lane.t_far)) {
      continue;
    }
    lane.t_best = lane.ray.t_max;
    lane.index = i;
    lane.state = State::kActive;
    std::size_t signs = 0;
    for (int a = 0; a < 3; ++a) signs |= std::size_t{ar.sign(lane.ray.inv_direction[a])} << a;
    by_signs[signs].push_back(lane);
  }

  std::array<Entry, kMaxStackDepth> stack;
  const std::uint32_t nodes_base = layout_.kd_nodes.offset;
  for (std::size_t signs = 0; signs < by_signs.size(); ++signs) {
    const std::vector<Lane>& group = by_signs[signs];
    for (std::size_t start = 0; start < group.size(); start += packet_rays) {
      std::array<Lane, kMaxPacketRays> lanes;
      const std::size_t n = std::min(packet_rays, group.size() - start);
      std::copy_n(group.begin() + static_cast<std::ptrdiff_t>(start), n, lanes.begin());
      ++shared.packets;
      const auto restart = [&] {
        ++shared.restarts;
        for (std::size_t r = 0; r < n; ++r) out[lanes[r].index] = trace_with(ar, rays[lanes[r].index], mode, none);
      };
      int stack_size = 0;
      std::uint32_t node_index = 0;
      bool restarted = false;
      while (!restarted) {
        const std::uint32_t node_address = nodes_base + spec::memory::kKdNodeBytes * node_index;
        const KdNode node{read_u32(image_, node_address + spec::memory::kKdNodeWord0At),
                          read_u32(image_, node_address + spec::memory::kKdNodeWord1At)};
        ++shared.node_fetches;
        for (std::size_t r = 0; r < n; ++r) {
          if (lanes[r].state == State::kActive) ++out[lanes[r].index].counters.nodes;
        }
        if (!node.is_leaf()) {
          const bool below_near = !(signs >> node.split_axis() & 1);
          const std::uint32_t near = below_near ? node_index + 1 : node.above_child();
          const std::uint32_t far = below_near ? node.above_child() : node_index + 1;
          std::array<InnerStep<V>, kMaxPacketRays> steps;
          std::uint32_t to_near = 0, to_far = 0, both = 0;
          for (std::size_t r = 0; r < n; ++r) {
            Lane& l = lanes[r];
            if (l.state != State::kActive) continue;
            steps[r] = inner_step(ar, l.ray, node, node_index, l.t_near, l.t_far);
            const std::uint32_t bit = 1u << r;
            if (steps[r].needs == Needs::kBoth) {
              if (steps[r].first != near) {  // never, by the sign argument above; safe if it did
                restarted = true;
                break;
              }
              both |= bit;
            } else if ((steps[r].needs == Needs::kFirst ? steps[r].first : steps[r].second) == near) {
              to_near |= bit;
            } else {
              to_far |= bit;
            }
          }
          if (restarted) break;
          if ((to_near | both) == 0) {
            node_index = far;  // every active ray goes on to the far child alone
            continue;
          }
          if ((to_far | both) != 0) {
            if (stack_size == stack_depth_) {
              restarted = true;
              break;
            }
            Entry& e = stack[static_cast<std::size_t>(stack_size++)];
            e.node = far;
            e.own = both;
            e.deferred = to_far;
            for (std::size_t r = 0; r < n; ++r) {
              Lane& l = lanes[r];
              if (both >> r & 1) {
                e.t_near[r] = steps[r].t_split;
                e.t_far[r] = l.t_far;
                l.t_far = steps[r].t_split;
              } else if (to_far >> r & 1) {
                e.t_near[r] = l.t_near;
                e.t_far[r] = l.t_far;
                l.state = State::kWaiting;
              }
            }
          }
          node_index = near;
          continue;
        }

        // A leaf: its references and records read once, each tested by every active ray.
        const std::uint32_t first_ref = node.first_prim_ref();
        for (std::size_t r = 0; r < n; ++r) {
          if (lanes[r].state == State::kActive) ++out[lanes[r].index].counters.leaves;
        }
        for (std::uint32_t k = 0; k < node.prim_count(); ++k) {
          std::size_t testing = 0;
          for (std::size_t r = 0; r < n; ++r) testing += lanes[r].state == State::kActive;
          if (testing == 0) break;
          const std::uint32_t ref_address = layout_.prim_refs.offset + spec::memory::kPrimRefBytes * (first_ref + k);
          const std::uint32_t prim = read_u32(image_, ref_address);
          const std::uint32_t record_address = layout_.isect_records.offset + record_bytes_ * prim;
          ++shared.ref_fetches;
          ++shared.record_fetches;
          IsectRecord words{};
          std::memcpy(words.data(), image_.data() + record_address, record_bytes_);
          for (std::size_t r = 0; r < n; ++r) {
            Lane& l = lanes[r];
            if (l.state != State::kActive) continue;
            TraceHit& result = out[l.index];
            ++result.counters.tests;
            UnitHit<Arith> hit;
            const bool found = watertight ? intersect_watertight(ar, l.ray, words, l.t_best, hit)
                                          : intersect_woop(ar, l.ray, words, l.t_best, hit);
            if (!found) continue;
            l.t_best = hit.t;
            result.hit = true;
            result.prim = prim;
            result.t = std::bit_cast<float>(fp::scale_fp32(ar.store(hit.t), kd_scale));
            result.u = std::bit_cast<float>(ar.store(hit.u));
            result.v = std::bit_cast<float>(ar.store(hit.v));
            if (mode == TraceMode::kAny) l.state = State::kDone;
          }
        }
        for (std::size_t r = 0; r < n; ++r) {
          Lane& l = lanes[r];
          if (l.state != State::kActive) continue;
          l.state = out[l.index].hit && ar.le(l.t_best, l.t_far) ? State::kDone : State::kWaiting;
        }
        // Pop until an entry holds a ray still walking; none left: every ray has ended.
        bool any = false;
        while (!any && stack_size > 0) {
          const Entry& e = stack[static_cast<std::size_t>(--stack_size)];
          for (std::size_t r = 0; r < n; ++r) {
            Lane& l = lanes[r];
            if (l.state != State::kWaiting || !((e.own | e.deferred) >> r & 1)) continue;
            if ((e.own >> r & 1) && out[l.index].hit && ar.lt(l.t_best, e.t_near[r])) {
              l.state = State::kDone;
              continue;
            }
            l.state = State::kActive;
            l.t_near = e.t_near[r];
            l.t_far = e.t_far[r];
            any = true;
          }
          node_index = e.node;
        }
        if (!any) break;
      }
      if (restarted) restart();
    }
  }
}

}  // namespace rpu::functional
