// A shader core's timing (docs/cycle-model.md "Shader cores", rtl/rpu_spu.sv): which of
// its chunks issues in which cycle, when each lane enters the pipeline (S0), when
// results, loads, sfu values and rays' answers are ready, and why the core waits when
// it does not issue. The functional shader core steps the chunks; this class decides
// when.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cycle/cycle_stats.hpp"
#include "cycle/dispatch.hpp"
#include "cycle/event_queue.hpp"
#include "cycle/memory_system.hpp"
#include "cycle/timeline.hpp"
#include "functional/shader_core.hpp"
#include "rpu/spec.hpp"

namespace rpu::cycle {

class CoreTiming {
 public:
  // No chunk has faulted.
  static constexpr std::uint32_t kNoFault = std::numeric_limits<std::uint32_t>::max();

  // The core's links to the rest of the chip, which the device wires.
  class Chip {
   public:
    virtual ~Chip() = default;
    // A trace's ray leaves for the dispatch, which it reaches at `at`.
    virtual void queue_ray(Ray ray, Cycle at) = 0;
    // Core `core`'s rays waiting at the dispatch.
    virtual std::size_t queued_rays(std::uint32_t core) const = 0;
    // The lanes of chunk `chunk` (counted over the chip) in round `round`, as
    // DeviceBase::lanes_of gives them: none past the frame's last pixel.
    virtual void round_lanes(std::uint64_t round, std::uint64_t chunk,
                             std::vector<functional::ShaderCore::Lane>& lanes) const = 0;
    // A chunk finished a round of pixels.
    virtual void round_done() = 0;
    // The first faulting pixel so far over the chip (kNoFault: none). A chunk whose
    // pixels all come after it stops, those before run on, so that the fault reported
    // is the first in pixel order (docs/shader-core.md "Faults").
    virtual std::uint32_t first_fault() const = 0;
    // A chunk faulted at `pixel`, before first_fault(): every core asks again which of
    // its chunks are ready.
    virtual void fault(std::uint32_t pixel) = 0;
    // The thread of `pixel` halted `cycles` after its round started.
    virtual void halted(std::uint32_t pixel, Cycle cycles) = 0;
  };

  // Core `index` of the chip; `shader` steps its chunks and counts in `stats`; its data
  // cache reads from `dram`; it wakes itself as agent `index` of `events`.
  CoreTiming(std::uint32_t index, const spec::HardwareConfig& config, functional::ShaderCore& shader,
             functional::ShaderStats& stats, Dram& dram, EventQueue& events, Timeline& timeline, Chip& chip);

  // The chunks take their first round of pixels; the core plans its first issue.
  void start();
  // Its wake-up at `now`: the first ready chunk after the one that issued last, round
  // robin, issues.
  void run(Cycle now);
  // A ray's answer leaves its traversal unit at `now`, for its register.
  void ray_answered(Ray& ray, Cycle now);
  // One of its rays left the dispatch's queue, which has room again from `at`.
  void ray_dispatched(Cycle at);
  // Another chunk faulted first: which chunks are ready is to be asked again.
  void forget_ready_times();
  // The launch ended at `end`: every cycle of the core in one of its times.
  ShaderCoreTime finish(Cycle end);

  // The cycles before this are accounted (the last lanes' S0 may come after the last
  // event).
  Cycle accounted() const { return accounted_; }
  const CacheStats& data_cache_stats() const { return data_cache_.stats(); }
  // The data cache's end-of-frame flush from cycle `at` (write-back): the cycle it is idle.
  Cycle flush_data_cache(Cycle at) { return data_cache_.flush(at); }
  // The fault of the chunk that faulted at `pixel`, or null.
  const functional::ShaderFault* fault_at(std::uint32_t pixel) const;
  // A chunk with pixels left to run, counted over the chip.
  std::optional<std::uint64_t> live_chunk() const;

 private:
  // Why the core did not issue: where its cycles without an issue are accounted.
  enum class Wait : std::uint8_t { kIdle, kTrace, kMemory, kDependency };

  struct ChunkSlot {
    functional::ShaderCore::Chunk chunk;
    std::uint64_t index = 0;  // counted over the chip: names its pixels (DeviceBase::lanes_of)
    std::uint64_t round = 0;
    bool live = false;
    bool halted = false;  // every lane halted, rays still in flight: the next round waits
    Cycle round_start = 0;
    Cycle earliest = 0;  // its last issue's lanes in the pipeline, the next pc picked and fetched
    std::vector<Cycle> reg_ready;
    std::vector<std::uint16_t> reg_rays;  // rays in flight that write the register
    int rays_in_flight = 0;
    Cycle loads_back = 0;  // its loads out are back in S0 by then
    // ready_time's answer, kept until an issue on its core, a ray's return or a new
    // round changes it: the core asks after every issue for each of its chunks.
    mutable bool ready_known = false;
    mutable Cycle ready_at = 0;
  };

  // A queue to a unit as rpu_spu counts its room: each lane handed to it counts from
  // the cycle after its E (S0 + 2) until the cycle it leaves.
  class UnitQueue {
   public:
    // A lane with S0 in `s0` that leaves before `out`; lanes gone by `s0` are forgotten.
    void add(Cycle s0, Cycle out);
    // The first cycle from `t` in which at most `room` lanes count.
    Cycle room(Cycle t, std::size_t room) const;

   private:
    std::deque<std::pair<Cycle, Cycle>> entries_;
  };

  void account(Cycle until);
  Cycle ready_time(const ChunkSlot& s) const;
  Cycle compute_ready_time(const ChunkSlot& s) const;
  void plan(Cycle from);
  Cycle issue(std::uint32_t i, Cycle now);
  void enter_lanes(const ChunkSlot& s, std::uint32_t pc, Cycle now);
  void time_issue(std::uint32_t i, std::uint32_t pc, Cycle now);
  Cycle time_sfu(const isa::Instruction& in);
  Cycle send_accesses();
  void send_rays(std::uint32_t i, int dst);
  Cycle lane_slot(std::size_t lane) const;
  void yield_to_returns(std::size_t lane);
  Cycle take_return_slot(Cycle at);
  Cycle send_access(Cycle s0, const functional::MemoryAccess& a);
  void set_result(ChunkSlot& s, int reg, Cycle ready);
  void fetch(std::uint32_t i, Cycle ready, Cycle now);
  void start_round(std::uint32_t i, Cycle at, Cycle now);

  std::uint32_t index_;
  const spec::HardwareConfig& config_;
  functional::ShaderCore& shader_;
  functional::ShaderStats& stats_;
  Cache data_cache_;
  EventQueue& events_;
  Timeline& timeline_;
  Chip& chip_;
  std::string track_;  // on the timeline

  std::vector<ChunkSlot> chunks_;
  std::size_t next_chunk_ = 0;  // round robin
  // The pipeline's entry (S0) takes one lane a cycle; a value handed back (a load's
  // data, an sfu result, a ray's answer) takes it first, so those cycles are reserved.
  Cycle seq_free_ = 0;             // the next chunk instruction may issue from here
  Cycle asked_ = 0;                // the cycle from which the core looks for a ready chunk
  std::set<Cycle> return_slots_;   // S0 cycles taken by values handed back
  Cycle lsu_free_ = 0;  // the next request the load/store unit takes
  // Per sfu (sfu_threads of them): the cycle it takes its next thread, the cycles it held
  // threads, its queue.
  std::vector<Cycle> sfu_free_;
  std::vector<std::uint64_t> sfu_busy_;
  std::multiset<Cycle> load_slots_;    // when each load in flight frees its miss register
  UnitQueue lsu_queue_;
  std::vector<UnitQueue> sfu_queues_;
  std::vector<Cycle> lane_slots_;      // the issuing instruction's lanes' S0 cycles
  std::map<Cycle, std::uint32_t> fetches_;  // the chunk that may issue from each cycle, its fetch two before
  Cycle accounted_ = 0;                // cycles before this are in `time_`
  Wait wait_ = Wait::kIdle;            // why it waits since `accounted_`
  ShaderCoreTime time_;
  functional::StepRecord record_;               // what the issuing step did
  std::vector<functional::TraceLog> spare_logs_;  // answered rays' storage, for the next
  std::vector<functional::ShaderCore::Lane> lanes_;
};

}  // namespace rpu::cycle
