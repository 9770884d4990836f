#include "functional/tracer.hpp"

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

  // §2 Clip to the scene box. The near and far plane of each axis are chosen by the
  // sign of 1/d (so +0 and -0 pick opposite planes); a NaN from 0 * inf (origin on a
  // plane, direction parallel to it) never narrows the interval.
  V t_near = ray.t_min, t_far = ray.t_max;
  const float lo[3] = {layout_.bounds_lo.x, layout_.bounds_lo.y, layout_.bounds_lo.z};
  const float hi[3] = {layout_.bounds_hi.x, layout_.bounds_hi.y, layout_.bounds_hi.z};
  for (int i = 0; i < 3; ++i) {
    const V t_lo = ar.mul(ar.sub(ar.load(std::bit_cast<std::uint32_t>(lo[i])), ray.origin[i]), ray.inv_direction[i]);
    const V t_hi = ar.mul(ar.sub(ar.load(std::bit_cast<std::uint32_t>(hi[i])), ray.origin[i]), ray.inv_direction[i]);
    const bool negative = ar.sign(ray.inv_direction[i]);
    const V entry = negative ? t_hi : t_lo;
    const V exit = negative ? t_lo : t_hi;
    if (ar.gt(entry, t_near)) t_near = entry;
    if (ar.lt(exit, t_far)) t_far = exit;
  }
  if (!ar.le(t_near, t_far)) return result;

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
      const int axis = node.split_axis();
      const V split = ar.load(node.split_bits());
      const V t_split = ar.mul(ar.sub(split, ray.origin[axis]), ray.inv_direction[axis]);
      const bool below_first = ar.lt(ray.origin[axis], split) ||
                               (ar.eq(ray.origin[axis], split) && ar.le(ray.direction[axis], ar.zero()));
      const std::uint32_t first = below_first ? node_index + 1 : node.above_child();
      const std::uint32_t second = below_first ? node.above_child() : node_index + 1;
      if (!ar.le(t_split, t_far) || ar.le(t_split, ar.zero())) {
        node_index = first;  // the plane is behind, beyond, or (NaN) the ray lies in it
      } else if (ar.lt(t_split, t_near)) {
        node_index = second;
      } else {
        if (stack_size == stack_depth_) {
          throw Error(fmt::format(
              "traversal stack overflow at kd node {} (stack depth {}): the image's tree is deeper than the "
              "traversal unit's stack; rebuild it with a max depth <= {}",
              node_index, stack_depth_, stack_depth_));
        }
        stack[stack_size++] = {second, t_split, t_far};
        node_index = first;
        t_far = t_split;
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

}  // namespace rpu::functional
