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
  log.ray = ray;
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

std::uint32_t Tracer::trace_packet(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                                   TraceLog& log) const {
  if (rays.empty() || rays.size() > kMaxPacketRays) {
    throw Error(fmt::format("a packet holds 1 to {} rays, not {}", kMaxPacketRays, rays.size()));
  }
  log.mode = mode;
  log.ray = rays[0];
  if (fast_) {
    const fp::fast32::FlushScope flush;
    return packet_with(Fast32Arith{}, rays, mode, out, log);
  }
  return packet_with(SoftArith{format_}, rays, mode, out, log);
}

std::uint32_t Tracer::direction_signs(const TraceRay& ray) const {
  const SoftArith ar{format_};
  RayRegisters<SoftArith> regs;
  if (!setup_ray(ar, ray, layout_.isect_mode == IsectMode::kWatertight, layout_.kd_scale_exponent, regs)) return 0;
  std::uint32_t signs = 0;
  for (int a = 0; a < 3; ++a) signs |= std::uint32_t{ar.sign(regs.inv_direction[a])} << a;
  return signs;
}

// A ray of a packet walk: its registers, interval and nearest hit, and whether it walks,
// waits for an entry of the packet's stack, or is done.
template <class Arith>
struct Tracer::PacketLane {
  using V = typename Arith::Value;
  enum class State : std::uint8_t { kActive, kWaiting, kDone };
  RayRegisters<Arith> ray;
  V t_near, t_far, t_best;
  std::size_t index;  // in the caller's rays and out
  State state;
};

namespace {
// What a packet walk reports: nothing, or the events of a traversal unit with packets
// (the cycle model's log: fetches, refs, each record with the rays that test it, and
// the node-step pipeline's passes after a leaf).
struct NoPacketRecorder {
  void operator()(TraceEvent::Kind, std::uint32_t, std::uint32_t = 1) const {}
};
struct PacketLogRecorder {
  TraceLog& log;
  void operator()(TraceEvent::Kind kind, std::uint32_t address, std::uint32_t rays = 1) const {
    log.events.push_back({kind, address, static_cast<std::uint8_t>(rays)});
  }
};
}  // namespace

// A packet walks as one ray would, with a mask: at an inner node each active ray takes its
// own step (inner_step); the packet visits the near child (by the packet's direction sign
// on the axis) if any ray goes there, and pushes the far child for the rays that go there
// too. A ray that needs both children pushes the far one as its own walk would (its
// first child is then always the near one: t_split > 0 puts its origin on the near side);
// a ray that needs only the far child defers to the entry and rejoins when it is popped,
// without the pop's test, since its own walk went there directly. After a leaf a ray
// waits for the next entry that holds it; an entry's own rays take its interval and the
// pop's test. So every ray visits its own walk's nodes in its own walk's order and ends
// where it ends. After a leaf the packet passes the node-step pipeline once per entry it
// pops, as rpu_tu_pipe does: a pass ends the rays whose hit lies within their interval,
// then ends the walk if no ray waits or the stack is empty, else pops an entry, and
// passes again while the entry woke no ray and others wait. A ray alone (`alone`) takes
// its own first child as the near one. True: the stack would overflow (a ray alone then
// faults there; a packet starts its rays again alone).
template <class Arith, class Recorder>
bool Tracer::walk_packet(const Arith& ar, std::span<PacketLane<Arith>> lanes, std::uint32_t signs, TraceMode mode,
                         std::span<TraceHit> out, PacketCounters& shared, const Recorder& record, bool alone) const {
  using V = typename Arith::Value;
  using Needs = typename InnerStep<V>::Needs;
  using State = typename PacketLane<Arith>::State;
  struct Entry {
    std::uint32_t node;
    std::array<V, kMaxPacketRays> t_near, t_far;
    std::uint32_t own = 0;       // rays whose own walk pushed it
    std::uint32_t deferred = 0;  // rays that rejoin here without a pop
  };
  const bool watertight = layout_.isect_mode == IsectMode::kWatertight;
  const int kd_scale = layout_.kd_scale_exponent;
  const std::size_t n = lanes.size();
  const std::uint32_t nodes_base = layout_.kd_nodes.offset;
  std::array<Entry, kMaxStackDepth> stack;
  int stack_size = 0;
  std::uint32_t node_index = 0;
  ++shared.packets;
  while (true) {
    const std::uint32_t node_address = nodes_base + spec::memory::kKdNodeBytes * node_index;
    const KdNode node{read_u32(image_, node_address + spec::memory::kKdNodeWord0At),
                      read_u32(image_, node_address + spec::memory::kKdNodeWord1At)};
    ++shared.node_fetches;
    record(node.is_leaf() ? TraceEvent::Kind::kLeaf : TraceEvent::Kind::kInner, node_address);
    for (std::size_t r = 0; r < n; ++r) {
      if (lanes[r].state == State::kActive) ++out[lanes[r].index].counters.nodes;
    }
    if (!node.is_leaf()) {
      const bool below_near = !(signs >> node.split_axis() & 1);
      std::uint32_t near = below_near ? node_index + 1 : node.above_child();
      std::uint32_t far = below_near ? node.above_child() : node_index + 1;
      std::array<InnerStep<V>, kMaxPacketRays> steps;
      std::uint32_t to_near = 0, to_far = 0, both = 0;
      for (std::size_t r = 0; r < n; ++r) {
        PacketLane<Arith>& l = lanes[r];
        if (l.state != State::kActive) continue;
        steps[r] = inner_step(ar, l.ray, node, node_index, l.t_near, l.t_far);
        if (alone) {
          near = steps[r].first;
          far = steps[r].second;
        }
        const std::uint32_t bit = 1u << r;
        if (steps[r].needs == Needs::kBoth) {
          if (steps[r].first != near) return true;  // never, by the sign argument above; safe if it did
          both |= bit;
        } else if ((steps[r].needs == Needs::kFirst ? steps[r].first : steps[r].second) == near) {
          to_near |= bit;
        } else {
          to_far |= bit;
        }
      }
      if ((to_near | both) == 0) {
        node_index = far;  // every active ray goes on to the far child alone
        continue;
      }
      if ((to_far | both) != 0) {
        if (stack_size == stack_depth_) return true;
        Entry& e = stack[static_cast<std::size_t>(stack_size++)];
        e.node = far;
        e.own = both;
        e.deferred = to_far;
        for (std::size_t r = 0; r < n; ++r) {
          PacketLane<Arith>& l = lanes[r];
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
      std::uint32_t testing = 0;
      for (std::size_t r = 0; r < n; ++r) testing += lanes[r].state == State::kActive;
      if (testing == 0) break;
      const std::uint32_t ref_address = layout_.prim_refs.offset + spec::memory::kPrimRefBytes * (first_ref + k);
      const std::uint32_t prim = read_u32(image_, ref_address);
      const std::uint32_t record_address = layout_.isect_records.offset + record_bytes_ * prim;
      ++shared.ref_fetches;
      ++shared.record_fetches;
      record(TraceEvent::Kind::kRef, ref_address);
      record(TraceEvent::Kind::kTest, record_address, testing);
      IsectRecord words{};
      std::memcpy(words.data(), image_.data() + record_address, record_bytes_);
      for (std::size_t r = 0; r < n; ++r) {
        PacketLane<Arith>& l = lanes[r];
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
    // The leaf's end: a ray whose hit lies within its interval is done, the others wait.
    bool waiting = false;
    for (std::size_t r = 0; r < n; ++r) {
      PacketLane<Arith>& l = lanes[r];
      if (l.state == State::kActive) {
        l.state = out[l.index].hit && ar.le(l.t_best, l.t_far) ? State::kDone : State::kWaiting;
      }
      waiting = waiting || l.state == State::kWaiting;
    }
    // Pop passes until an entry wakes a ray; none waiting or none left: the walk ends.
    bool woke = false;
    while (!woke) {
      record(TraceEvent::Kind::kPop, 0);
      if (!waiting || stack_size == 0) return false;
      const Entry& e = stack[static_cast<std::size_t>(--stack_size)];
      waiting = false;
      for (std::size_t r = 0; r < n; ++r) {
        PacketLane<Arith>& l = lanes[r];
        if (l.state != State::kWaiting) continue;
        if (!((e.own | e.deferred) >> r & 1)) {
          waiting = true;
          continue;
        }
        if ((e.own >> r & 1) && out[l.index].hit && ar.lt(l.t_best, e.t_near[r])) {
          l.state = State::kDone;
          continue;
        }
        l.state = State::kActive;
        l.t_near = e.t_near[r];
        l.t_far = e.t_far[r];
        woke = true;
      }
      node_index = e.node;
      if (!woke && !waiting) return false;
    }
  }
}

// The rays that enter the tree, set up for a packet walk; false for a ray that misses
// the set-up or the scene box (its result stays the empty one, as alone).
template <class Arith>
bool Tracer::packet_lane(const Arith& ar, const TraceRay& ray, std::size_t index, PacketLane<Arith>& lane) const {
  const bool watertight = layout_.isect_mode == IsectMode::kWatertight;
  if (!setup_ray(ar, ray, watertight, layout_.kd_scale_exponent, lane.ray) ||
      !clip_to_scene(ar, lane.ray, layout_, lane.t_near, lane.t_far)) {
    return false;
  }
  lane.t_best = lane.ray.t_max;
  lane.index = index;
  lane.state = PacketLane<Arith>::State::kActive;
  return true;
}

template <class Arith>
std::uint32_t Tracer::signs_of(const Arith& ar, const PacketLane<Arith>& lane) {
  std::uint32_t signs = 0;
  for (int a = 0; a < 3; ++a) signs |= std::uint32_t{ar.sign(lane.ray.inv_direction[a])} << a;
  return signs;
}

template <class Arith>
void Tracer::packets_with(const Arith& ar, std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                          std::size_t packet_rays, PacketCounters& shared) const {
  NoRecorder none;
  const NoPacketRecorder quiet;
  // The rays that enter the tree, grouped by the signs of their directions.
  std::array<std::vector<PacketLane<Arith>>, 8> by_signs;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    out[i] = TraceHit{};
    PacketLane<Arith> lane;
    if (packet_lane(ar, rays[i], i, lane)) by_signs[signs_of(ar, lane)].push_back(lane);
  }
  for (std::uint32_t signs = 0; signs < by_signs.size(); ++signs) {
    const std::vector<PacketLane<Arith>>& group = by_signs[signs];
    for (std::size_t start = 0; start < group.size(); start += packet_rays) {
      std::array<PacketLane<Arith>, kMaxPacketRays> lanes;
      const std::size_t n = std::min(packet_rays, group.size() - start);
      std::copy_n(group.begin() + static_cast<std::ptrdiff_t>(start), n, lanes.begin());
      if (walk_packet(ar, std::span(lanes).first(n), signs, mode, out, shared, quiet, false)) {
        // A packet whose stack fills starts its rays again alone, each as trace().
        ++shared.restarts;
        for (std::size_t r = 0; r < n; ++r) out[lanes[r].index] = trace_with(ar, rays[lanes[r].index], mode, none);
      }
    }
  }
}

// One packet as the traversal unit walks it (rpu_tu_pipe with Packet > 1); a packet
// whose stack fills walks its rays again one by one, each alone from its set-up, and a
// ray alone whose stack overflows faults (its bit in the result).
template <class Arith>
std::uint32_t Tracer::packet_with(const Arith& ar, std::span<const TraceRay> rays, TraceMode mode,
                                  std::span<TraceHit> out, TraceLog& log) const {
  const PacketLogRecorder record{log};
  PacketCounters shared;
  std::array<PacketLane<Arith>, kMaxPacketRays> lanes;
  std::size_t n = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    out[i] = TraceHit{};
    if (!packet_lane(ar, rays[i], i, lanes[n])) throw Error("a packet's ray misses the scene box: it never joins one");
    if (signs_of(ar, lanes[n]) != signs_of(ar, lanes[0])) throw Error("a packet's rays differ in direction signs");
    ++n;
  }
  const std::array<PacketLane<Arith>, kMaxPacketRays> set_up = lanes;
  const std::span<PacketLane<Arith>> all = std::span(lanes).first(n);
  if (!walk_packet(ar, all, signs_of(ar, lanes[0]), mode, out, shared, record, n == 1)) return 0;
  if (n == 1) return 1;
  std::uint32_t faults = 0;
  for (std::size_t r = 0; r < n; ++r) {
    lanes[r] = set_up[r];
    out[r] = TraceHit{};
    if (walk_packet(ar, std::span(lanes).subspan(r, 1), signs_of(ar, lanes[r]), mode, out, shared, record, true)) {
      faults |= 1u << r;
    }
  }
  return faults;
}

}  // namespace rpu::functional
