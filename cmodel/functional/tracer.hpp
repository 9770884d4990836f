#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fp/format.hpp"
#include "functional/arith.hpp"
#include "functional/intersection_unit.hpp"
#include "functional/trace_types.hpp"
#include "memory/memory_image.hpp"

namespace rpu::functional {

// The golden traversal unit and intersection unit: kd-tree traversal with a fixed-depth
// stack over a validated memory image, in the configured number format, bit for bit
// the semantics the RTL implements (docs/traversal.md).
// One ray's walk as the memory accesses and steps of the units, in order: what the
// cycle model times (docs/cycle-model.md). Addresses are byte offsets in the image.
struct TraceEvent {
  enum class Kind : std::uint8_t {
    kInner,  // an inner node fetched and stepped (address of the node)
    kLeaf,   // a leaf fetched (address of the node)
    kRef,    // a leaf's primitive reference read (address of the 4-byte ref)
    kTest,   // an intersection record read and tested in the IU (address of the record)
    kPop,    // a stack entry popped; in a packet's log, a pass of the node-step pipeline after a leaf
  };
  Kind kind;
  std::uint32_t address;
  std::uint8_t rays = 1;  // kTest in a packet's log: the rays that test the record
};

// One intersection-unit test as the unit sees it, in the format (SoftArith bits): the
// ray registers, the record's words as read from the image, t_best, and the result
// (t, u, v zero on a miss). What the RTL intersection unit is compared with.
struct IuTest {
  RayRegisters<SoftArith> ray;
  IsectRecord record;
  std::uint32_t t_best;
  bool hit;
  UnitHit<SoftArith> result;
};

struct TraceLog {
  std::vector<TraceEvent> events;
  TraceMode mode = TraceMode::kClosest;
  TraceRay ray{};  // the ray walked (a packet's log: its first)
};

// What packets of rays share (docs/traversal.md "Packets"): a packet's walk fetches a
// node, a leaf's references and its records once for every ray of it active there.
struct PacketCounters {
  std::uint64_t packets = 0;         // walks of rays together (one ray alone is one too)
  std::uint64_t node_fetches = 0;    // kd nodes fetched (inner and leaf)
  std::uint64_t ref_fetches = 0;     // primitive references read
  std::uint64_t record_fetches = 0;  // intersection records read
  std::uint64_t restarts = 0;        // packets whose stack filled: their rays walked again alone
};

// The most rays a packet holds.
inline constexpr std::size_t kMaxPacketRays = 8;

class Tracer {
 public:
  // `image` must outlive the tracer and have passed validate_memory_image, which gave
  // `layout`. With fp32 and `fast_path`, arithmetic runs on host float (identical bits).
  Tracer(std::span<const std::uint8_t> image, const ImageLayout& layout, fp::Format format, int stack_depth,
         bool fast_path = true);

  // Throws rpu::Error if the ray needs a deeper stack than the unit has. With `log`,
  // also records the walk (the result is the same).
  TraceHit trace(const TraceRay& ray, TraceMode mode) const;
  TraceHit trace(const TraceRay& ray, TraceMode mode, TraceLog& log) const;

  // With `tests`, also records every IU test of the walk (always on SoftArith, also for
  // fp32: bit for bit the same result). For the RTL co-simulation (sim/iu_cosim.cpp).
  TraceHit trace(const TraceRay& ray, TraceMode mode, std::vector<IuTest>& tests) const;

  // Many rays at once; out.size() must equal rays.size().
  void trace(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out) const;

  // Rays that walk the tree together (docs/traversal.md "Packets"): those whose
  // directions have the same signs, up to `packet_rays` at a time, in their order. Each
  // ray's hit and counters are exactly what trace() gives it alone; `shared` counts what
  // the packets fetched. out.size() must equal rays.size().
  void trace_packets(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                     std::size_t packet_rays, PacketCounters& shared) const;

  // One packet as a traversal unit with packets walks it (docs/rtl.md "The node-step
  // pipeline", Packets): `rays` (1 to kMaxPacketRays, each entering the scene box, all of
  // the same direction signs) in the packet's order. Appends the walk's fetches, each
  // record with the rays that test it, and the passes after each leaf to `log`; out[i]
  // is ray i's result, as trace() gives it. A packet whose stack would overflow walks its
  // rays again one by one; returns the rays that fault alone (bit i: ray i).
  std::uint32_t trace_packet(std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                             TraceLog& log) const;

  // The sign bits of the ray's inv direction in the format (bit a: axis a), by which a
  // traversal unit with packets groups rays.
  std::uint32_t direction_signs(const TraceRay& ray) const;

  fp::Format format() const { return format_; }
  bool uses_fast_path() const { return fast_; }

 private:
  template <class Arith, class Recorder>
  TraceHit trace_with(const Arith& ar, const TraceRay& ray, TraceMode mode, Recorder& recorder) const;
  template <class Arith>
  struct PacketLane;
  template <class Arith>
  bool packet_lane(const Arith& ar, const TraceRay& ray, std::size_t index, PacketLane<Arith>& lane) const;
  template <class Arith>
  static std::uint32_t signs_of(const Arith& ar, const PacketLane<Arith>& lane);
  template <class Arith, class Recorder>
  bool walk_packet(const Arith& ar, std::span<PacketLane<Arith>> lanes, std::uint32_t signs, TraceMode mode,
                   std::span<TraceHit> out, PacketCounters& shared, const Recorder& record, bool alone) const;
  template <class Arith>
  void packets_with(const Arith& ar, std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                    std::size_t packet_rays, PacketCounters& shared) const;
  template <class Arith>
  std::uint32_t packet_with(const Arith& ar, std::span<const TraceRay> rays, TraceMode mode, std::span<TraceHit> out,
                            TraceLog& log) const;

  std::span<const std::uint8_t> image_;
  ImageLayout layout_;
  fp::Format format_;
  int stack_depth_;
  std::uint32_t record_bytes_;  // of an intersection record in the image's mode
  bool fast_;
};

}  // namespace rpu::functional
