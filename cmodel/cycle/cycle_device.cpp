// The cycle backend: the functional core computes, this model times (docs/cycle-model.md).
// An event loop over cycles (cycle/event_queue.hpp): shader cores and traversal units
// are woken at the cycle their next step can happen.
#include "cycle/cycle_device.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <deque>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "common/error.hpp"
#include "device/device_base.hpp"
#include "fp/fast32.hpp"
#include "cycle/dispatch.hpp"
#include "cycle/event_queue.hpp"
#include "cycle/tu_pipe_timing.hpp"
#include "cycle/walker_timing.hpp"
#include "functional/tracer.hpp"
#include "rpu/streams.hpp"

namespace rpu::cycle {

namespace {

namespace si = spec::isa;
using functional::ShaderCore;
using functional::StepRecord;
using functional::TraceEvent;
using functional::TraceLog;
using isa::Opcode;

// Why a shader core did not issue: where its idle cycles are accounted.
enum class Wait : std::uint8_t { kIdle, kTrace, kMemory, kDependency };

struct ChunkSlot {
  ShaderCore::Chunk chunk;
  std::uint64_t index = 0;  // counted over the chip: names its pixels (DeviceBase::lanes_of)
  std::uint32_t core = 0;
  std::uint64_t round = 0;
  bool live = false;
  bool halted = false;  // every lane halted, rays still in flight: the next round waits
  Cycle round_start = 0;
  Cycle earliest = 0;  // its last issue's lanes in the pipeline, the next pc picked and fetched
  std::vector<Cycle> reg_ready;
  std::vector<std::uint16_t> reg_rays;  // rays in flight that write the register
  int rays_in_flight = 0;
  Cycle loads_back = 0;  // its loads out are back in S0 by then
  // ready_time's answer, kept until an issue on its core, a ray's return or a new round
  // changes it: the core asks after every issue for each of its chunks.
  mutable bool ready_known = false;
  mutable Cycle ready_at = 0;
};

struct Core {
  std::vector<ChunkSlot> chunks;
  std::size_t next_chunk = 0;  // round robin
  // The pipeline's entry (S0) takes one lane a cycle; a value handed back (a load's
  // data, an sfu result, a ray's answer) takes it first, so those cycles are reserved.
  Cycle seq_free = 0;              // the next chunk instruction may issue from here
  std::set<Cycle> return_slots;    // S0 cycles taken by values handed back
  Cycle lsu_free = 0, sfu_free = 0;  // the next request the load/store unit, the sfu takes
  std::deque<Cycle> sfu_starts;      // when the sfu starts each thread instruction it holds
  std::vector<Cycle> lane_slots;   // the issuing instruction's lanes' S0 cycles
  Cycle accounted = 0;         // cycles before this are in `time`
  Wait wait = Wait::kIdle;     // why it waits since `accounted`
  std::unique_ptr<Cache> data_cache;
  ShaderCoreTime time;
};

// The chip's ray units read through the node and triangle caches.
class CacheLines final : public LineSource {
 public:
  CacheLines(Cache& nodes, Cache& triangles) : nodes_(nodes), triangles_(triangles) {}
  Cycle read(Cycle now, std::uint32_t address, std::uint32_t bytes, bool node) override {
    return (node ? nodes_ : triangles_).read(now, address, bytes);
  }

 private:
  Cache& nodes_;
  Cache& triangles_;
};

class CycleDevice final : public device::DeviceBase, RayUnitTiming::Ports {
 public:
  CycleDevice(const spec::HardwareConfig& config, fp::Format format, const CycleOptions& options)
      : DeviceBase(config, format),
        options_(options),
        timeline_(options.timeline_begin, options.timeline_end, options.timeline_max_slices, options.timeline) {}
  ~CycleDevice() override { end_frame(); }

  std::string_view backend() const override { return "cycle"; }

 private:
  void run(const ProgressCallback& progress) override;

  // The event queue's agents: the cores, then the ray units.
  void schedule_core(std::uint32_t c, Cycle at) { events_->wake(c, at); }
  void wake_unit(std::size_t u, Cycle at) { events_->wake(static_cast<std::uint32_t>(cores_.size() + u), at); }
  void account(Core& core, Cycle until);
  Cycle ready_time(const ChunkSlot& s) const;
  Cycle compute_ready_time(const ChunkSlot& s) const;
  void plan(std::uint32_t c, Cycle from);
  void core_event(std::uint32_t c, Cycle now);
  Cycle issue(std::uint32_t c, std::uint32_t i, Cycle now);
  void time_issue(std::uint32_t c, std::uint32_t i, std::uint32_t pc, Cycle now);
  Cycle take_return_slot(Core& core, Cycle at);
  Cycle send_access(Core& core, Cycle s0, const functional::MemoryAccess& a);
  void start_round(std::uint32_t c, std::uint32_t i, Cycle at);
  void dispatch(Ray&& ray, Cycle at);
  void ray_left_queue(std::uint32_t c, Cycle at);
  // The ray units' ports.
  std::optional<Ray> next_ray(Cycle from) override;
  std::optional<Ray> send_ray(Cycle now) override;
  bool rays_waiting() const override { return dispatch_->any_waiting(); }
  void answer(Ray& ray, Cycle now) override;
  void make_ray_units();
  void set_result(ChunkSlot& s, int reg, Cycle ready);
  void finish(Cycle end);

  CycleOptions options_;

  // One frame's state (run() sets it up).
  std::optional<functional::Tracer> tracer_;
  std::optional<ShaderCore> shader_;
  functional::ShaderStats shader_stats_;
  StepRecord record_;
  std::optional<Dram> dram_;
  std::optional<Cache> node_cache_, triangle_cache_;
  std::vector<Core> cores_;
  // Walkers, or pipelined units: traversal unit u's walkers at u * walkers_ ...
  std::vector<std::unique_ptr<RayUnitTiming>> units_;
  std::uint32_t walkers_ = 1;  // per traversal unit
  std::vector<IuTimer> ius_;
  std::optional<CacheLines> lines_;
  std::optional<RayDispatch> dispatch_;
  std::vector<TraceLog> spare_logs_;
  std::optional<EventQueue> events_;
  std::uint64_t rounds_done_ = 0, rounds_total_ = 0;
  const ProgressCallback* progress_ = nullptr;
  std::vector<functional::ShaderCore::Lane> lanes_;
  // The first faulting pixel so far (none: kNoFault). Chunks whose pixels all come
  // after it stop; those before it run on, so that the fault reported is the first in
  // pixel order, the functional backend's (docs/shader-core.md "Faults").
  static constexpr std::uint32_t kNoFault = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t fault_pixel_ = kNoFault;
  Timeline timeline_;
  CycleStats out_;    // this launch's
  CycleStats frame_;  // the frame's: a selected frame's two launches added
};

void CycleDevice::account(Core& core, Cycle until) {
  if (until <= core.accounted) return;
  const Cycle n = until - core.accounted;
  switch (core.wait) {
    case Wait::kIdle: core.time.idle += n; break;
    case Wait::kTrace: core.time.wait_trace += n; break;
    case Wait::kMemory: core.time.wait_memory += n; break;
    case Wait::kDependency: core.time.wait_dependency += n; break;
  }
  core.accounted = until;
}

// The first cycle the chunk's next instruction can issue (its sources and destination
// ready: an in-order scoreboard; room in the queue it hands its lanes to), or kNever
// while a ray it needs is in flight.
Cycle CycleDevice::ready_time(const ChunkSlot& s) const {
  if (!s.ready_known) {
    s.ready_at = compute_ready_time(s);
    s.ready_known = true;
  }
  return s.ready_at;
}

Cycle CycleDevice::compute_ready_time(const ChunkSlot& s) const {
  if (!s.live || s.halted || s.chunk.threads().front().lane.pixel > fault_pixel_) return kNever;
  Cycle t = s.earliest;
  const std::uint32_t pc = s.chunk.next_pc();
  if (!shader_->instruction(pc)) return t;  // the step will fault
  const isa::RegisterUse& use = shader_->register_use(pc);
  const auto need = [&](int r) {
    if (r < 0 || static_cast<std::size_t>(r) >= s.reg_ready.size()) return true;  // the step will fault
    if (s.reg_rays[static_cast<std::size_t>(r)]) return false;
    t = std::max(t, s.reg_ready[static_cast<std::size_t>(r)]);
    return true;
  };
  if (!need(use.dst) || !need(use.data) || !need(use.src[0]) || !need(use.src[1]) || !need(use.src[2])) {
    return kNever;
  }
  // The queue the instruction hands its lanes to must have room for all of them and for
  // lanes of the instruction before still on their way (rpu_spu's QueueDepth and
  // QueueNeed): at most UnitQueueChunks - 1 chunks of lanes may wait in it.
  // (So the answer depends on the core's queues too: every issue on the core asks again.)
  const Core& core = cores_[s.core];
  const auto room = static_cast<std::size_t>(streams::kUnitQueueChunks - 1) *
                    static_cast<std::size_t>(config_.chunk_size);
  const isa::Instruction& in = *shader_->instruction(pc);
  if (in.spec->cls == si::Class::kTrace && dispatch_->waiting(s.core) > room) return kNever;
  if (in.spec->cls == si::Class::kMem || in.opcode() == Opcode::kCalli) {
    t = std::max(t, core.lsu_free - std::min<Cycle>(core.lsu_free, room));
  }
  if (in.spec->cls == si::Class::kSfu && core.sfu_starts.size() > room) {
    t = std::max(t, core.sfu_starts[core.sfu_starts.size() - 1 - room]);
  }
  return t;
}

// Schedules the core's next issue at or after `from`, and notes why it waits until then
// as the RTL's counters do (docs/chip.md "Statistics"): for its own pipeline while a live
// chunk has neither rays nor loads out, else for memory while one has loads out, else
// for rays.
void CycleDevice::plan(std::uint32_t c, Cycle from) {
  Core& core = cores_[c];
  Cycle best = kNever;
  bool own = false, loads = false, rays = false;
  for (const ChunkSlot& s : core.chunks) {
    best = std::min(best, ready_time(s));
    if (!s.live) continue;
    if (s.rays_in_flight) {
      rays = true;
    } else if (s.loads_back > from) {
      loads = true;
    } else {
      own = true;
    }
  }
  core.wait = own ? Wait::kDependency : loads ? Wait::kMemory : rays ? Wait::kTrace : Wait::kIdle;
  if (best != kNever) schedule_core(c, std::max({best, from, core.seq_free}));
}

void CycleDevice::core_event(std::uint32_t c, Cycle now) {
  Core& core = cores_[c];
  account(core, now);
  const auto n = static_cast<std::uint32_t>(core.chunks.size());
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::uint32_t>((core.next_chunk + k) % n);
    if (ready_time(core.chunks[i]) > now) continue;
    core.next_chunk = i + 1;
    for (ChunkSlot& other : core.chunks) other.ready_known = false;
    // Busy from the issue to its last lane's S0 (the next issue may share that cycle).
    const Cycle last = issue(c, i, now);
    core.time.busy += last + 1 - std::max(now, core.accounted);
    core.accounted = last + 1;
    break;
  }
  plan(c, now + 1);
}

// The first S0 cycle from `at` that no other value handed back has taken.
Cycle CycleDevice::take_return_slot(Core& core, Cycle at) {
  auto it = core.return_slots.lower_bound(at);
  while (it != core.return_slots.end() && *it == at) {
    ++at;
    ++it;
  }
  core.return_slots.insert(it, at);
  return at;
}

// A lane's access (its S0 in `s0`) through the load/store unit: in program order, one
// piece a cycle onto the data cache's port. A load's data comes back through S0: returns
// that cycle (0 for a store).
Cycle CycleDevice::send_access(Core& core, Cycle s0, const functional::MemoryAccess& a) {
  const Cycle at = std::max(s0 + static_cast<Cycle>(config_.latency.to_unit), core.lsu_free);
  core.lsu_free = at + port_pieces(a.address, a.bytes);
  if (a.store) {
    core.data_cache->write(at, a.address, a.bytes);
    return 0;
  }
  return take_return_slot(core, core.data_cache->read(at, a.address, a.bytes) + static_cast<Cycle>(config_.latency.from_unit));
}

void CycleDevice::set_result(ChunkSlot& s, int reg, Cycle ready) {
  const auto r = static_cast<std::size_t>(reg);
  // A register the configuration lacks faulted the step's lanes: no result to time.
  if (reg < 0 || r >= s.reg_ready.size()) return;
  s.reg_ready[r] = ready;
}

// Issues the chunk's next instruction; returns the S0 cycle of its last lane.
Cycle CycleDevice::issue(std::uint32_t c, std::uint32_t i, Cycle now) {
  Core& core = cores_[c];
  ChunkSlot& s = core.chunks[i];
  const std::uint32_t pc = s.chunk.next_pc();
  // Its lanes: those standing at the pc enter S0 one a cycle, in cycles no value
  // handed back has taken.
  std::size_t lanes = 0;
  for (const ShaderCore::Thread& t : s.chunk.threads()) lanes += !t.done && t.pc == pc;
  core.return_slots.erase(core.return_slots.begin(), core.return_slots.upper_bound(now));
  core.lane_slots.clear();
  auto taken = core.return_slots.begin();
  for (Cycle at = now + 1; core.lane_slots.size() < std::max<std::size_t>(lanes, 1); ++at) {
    if (taken != core.return_slots.end() && *taken == at) {
      ++taken;
    } else {
      core.lane_slots.push_back(at);
    }
  }
  const Cycle last = core.lane_slots.back();
  core.seq_free = last;
  shader_->step(s.chunk, shader_stats_, &record_);
  if (const functional::ShaderFault* f = s.chunk.fault(); f && f->pixel() < fault_pixel_) {
    fault_pixel_ = f->pixel();
    for (Core& other : cores_) {
      for (ChunkSlot& slot : other.chunks) slot.ready_known = false;
    }
  }
  ++core.time.chunk_issues;
  s.earliest = last + static_cast<Cycle>(config_.latency.reissue);
  // A step whose every lane faulted at an illegal pc has no instruction to time.
  if (record_.insn) time_issue(c, i, pc, now);
  if (s.chunk.done()) {
    if (s.rays_in_flight) {
      s.halted = true;
    } else {
      start_round(c, i, s.earliest);
    }
  }
  return last;
}

// When the results of the step just issued are ready, and the memory and rays it sends:
// lane k entered S0 in core.lane_slots[k]; results pass the datapath (latency.result);
// loads, sfu operations and rays go to their unit latency.to_unit later, and their
// values come back through S0.
void CycleDevice::time_issue(std::uint32_t c, std::uint32_t i, std::uint32_t pc, Cycle now) {
  Core& core = cores_[c];
  ChunkSlot& s = core.chunks[i];
  const isa::Instruction& in = *record_.insn;
  const isa::RegisterUse& use = shader_->register_use(pc);
  const spec::LatencyConfig& lat = config_.latency;
  const Opcode op = in.opcode();
  const auto result = static_cast<Cycle>(lat.result), to_unit = static_cast<Cycle>(lat.to_unit),
             from_unit = static_cast<Cycle>(lat.from_unit);
  const std::vector<Cycle>& slots = core.lane_slots;
  const auto lane_slot = [&](std::size_t k) { return slots[std::min(k, slots.size() - 1)]; };
  switch (in.spec->cls) {
    case si::Class::kFpu:
    case si::Class::kInt:
    case si::Class::kSpecial: set_result(s, use.dst, slots.back() + result); break;
    case si::Class::kSfu: {
      // One thread's instruction at a time; each divider takes its share of the written
      // lanes back to back, one cycle apart.
      const auto units = static_cast<Cycle>(config_.sfu_units);
      const auto passes = (static_cast<Cycle>(std::popcount(in.wmask)) + units - 1) / units;
      const auto each = static_cast<Cycle>(op == Opcode::kRsq ? lat.rsq : lat.sfu) + 1;
      Cycle done = 0;
      while (!core.sfu_starts.empty() && core.sfu_starts.front() <= now) core.sfu_starts.pop_front();
      for (std::size_t k = 0; k < static_cast<std::size_t>(std::popcount(record_.lanes)); ++k) {
        const Cycle start = std::max(lane_slot(k) + to_unit, core.sfu_free);
        core.sfu_starts.push_back(start);
        const Cycle out = start + passes * each - 1 + from_unit;
        core.sfu_free = out + 1;
        done = std::max(done, take_return_slot(core, out));
      }
      set_result(s, use.dst, done + result);
      break;
    }
    case si::Class::kBranch: {
      // calli reads its target from the shader table, one read per lane; the chunk
      // picks its next pc when the last has come back.
      Cycle back = 0;
      for (std::size_t k = 0; k < record_.accesses.size(); ++k) {
        back = std::max(back, send_access(core, lane_slot(k), record_.accesses[k]));
      }
      s.earliest = std::max(s.earliest, back + static_cast<Cycle>(lat.reissue));
      s.loads_back = std::max(s.loads_back, back);
      break;
    }
    case si::Class::kMem: {
      bool load = false;
      Cycle done = 0;
      for (std::size_t k = 0; k < record_.accesses.size(); ++k) {
        load |= !record_.accesses[k].store;
        done = std::max(done, send_access(core, lane_slot(k), record_.accesses[k]));
      }
      if (load) {
        set_result(s, use.dst, done + result);
        s.loads_back = std::max(s.loads_back, done);
      }
      break;
    }
    case si::Class::kTrace:
      for (std::size_t k = 0; k < record_.trace_count; ++k) {
        Ray ray;
        ray.core = c;
        ray.chunk = i;
        ray.dst = static_cast<std::uint32_t>(use.dst);
        std::swap(ray.log, record_.traces[k]);
        if (!spare_logs_.empty()) {  // reuse a finished ray's storage
          std::swap(record_.traces[k], spare_logs_.back());
          spare_logs_.pop_back();
        }
        ++s.reg_rays[static_cast<std::size_t>(use.dst)];
        ++s.rays_in_flight;
        dispatch(std::move(ray), lane_slot(k) + to_unit);
      }
      break;
  }
  if (timeline_.enabled()) {
    timeline_.add(fmt::format("core {}", c), fmt::format("chunk {}: {}", i, in.spec->mnemonic), now, now + 1);
  }
  if (op == Opcode::kHalt) {
    for (std::size_t l = 0; l < s.chunk.threads().size(); ++l) {
      if (record_.lanes >> l & 1) {
        out_.pixel_cycles[s.chunk.threads()[l].lane.pixel] = static_cast<std::uint32_t>(now + 1 - s.round_start);
      }
    }
  }
}

// The chunk's current round is over: it takes its next round of pixels, if any.
void CycleDevice::start_round(std::uint32_t c, std::uint32_t i, Cycle at) {
  ChunkSlot& s = cores_[c].chunks[i];
  s.ready_known = false;
  if (s.live) {
    ++rounds_done_;
    if (*progress_) (*progress_)(rounds_done_, rounds_total_);
    ++s.round;
  }
  s.halted = false;
  lanes_of(s.round, s.index, lanes_);
  // A chunk that faulted keeps its fault: its next round's pixels all come after it.
  s.live = !lanes_.empty() && lanes_.front().pixel < fault_pixel_;
  if (!s.live) return;
  shader_->start(s.chunk, lanes_, shader_stats_);
  s.round_start = at;
  s.earliest = at;
  std::fill(s.reg_ready.begin(), s.reg_ready.end(), at);
}

// The ray waits in its core's queue until a traversal unit takes it. The units are
// offered it in turn, then their next walkers: units fill evenly.
void CycleDevice::dispatch(Ray&& ray, Cycle at) {
  dispatch_->queue(std::move(ray), at);
  const auto tus = static_cast<std::size_t>(config_.traversal_units);
  for (std::size_t k = 0; k < units_.size(); ++k) {
    const std::size_t u = (k % tus) * walkers_ + k / tus;
    wake_unit(u, units_[u]->ray_waiting(at));
  }
}

// A traversal unit took a ray of core `c`: its queue has room again from `at`.
void CycleDevice::ray_left_queue(std::uint32_t c, Cycle at) {
  for (ChunkSlot& s : cores_[c].chunks) s.ready_known = false;
  plan(c, at);
}

std::optional<Ray> CycleDevice::next_ray(Cycle from) {
  std::optional<Ray> ray = dispatch_->next();
  if (ray) ray_left_queue(ray->core, from);
  return ray;
}

std::optional<Ray> CycleDevice::send_ray(Cycle now) {
  std::optional<Ray> ray = dispatch_->send(now);
  if (ray) ray_left_queue(ray->core, now);
  return ray;
}

// The ray's answer enters its core's pipeline and is written like any result.
void CycleDevice::answer(Ray& ray, Cycle now) {
  const std::uint32_t c = ray.core, i = ray.chunk;
  Core& core = cores_[c];
  ChunkSlot& s = core.chunks[i];
  const auto dst = static_cast<std::size_t>(ray.dst);
  s.ready_known = false;
  const auto from_unit = static_cast<Cycle>(config_.tu_pipe ? config_.tu.pipe_from_unit : config_.latency.from_rays);
  const Cycle back = take_return_slot(core, now + from_unit) +
                     static_cast<Cycle>(config_.latency.result);
  s.reg_ready[dst] = std::max(s.reg_ready[dst], back);
  --s.reg_rays[dst];
  --s.rays_in_flight;
  account(core, now);  // the wait so far had the old reason
  if (s.halted && !s.rays_in_flight) start_round(c, i, back);
  plan(c, now + 1);
  spare_logs_.push_back(std::move(ray.log));
}

// The traversal units: `tu_slots` walkers each, or a pipelined unit each (tu_pipe).
void CycleDevice::make_ray_units() {
  ius_.assign(static_cast<std::size_t>(config_.intersection_units), IuTimer{});
  units_.clear();
  RayUnitTiming::Ports& ports = *this;
  for (int u = 0; u < config_.traversal_units; ++u) {
    if (config_.tu_pipe) {
      units_.push_back(std::make_unique<PipeUnitTiming>(PipeCosts::of(config_, layout_.isect_mode), *lines_, ius_, ports));
      continue;
    }
    for (std::uint32_t s = 0; s < walkers_; ++s) {
      std::string track = walkers_ == 1 ? fmt::format("TU {}", u) : fmt::format("TU {} slot {}", u, s);
      units_.push_back(std::make_unique<WalkerTiming>(WalkCosts::of(config_, layout_.isect_mode), *lines_, ius_, ports,
                                                      timeline_, std::move(track)));
    }
  }
}

void CycleDevice::run(const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  tracer_.emplace(image_, layout_, format_, config_.stack_depth);
  shader_.emplace(firmware_, *memory_, *tracer_, format_, core_config(options_.watchdog));
  shader_stats_ = {};
  dram_.emplace(config_.dram);
  const auto line_wait = static_cast<Cycle>(config_.latency.line_wait);
  node_cache_.emplace(config_.node_cache, *dram_, line_wait);
  triangle_cache_.emplace(config_.triangle_cache, *dram_, line_wait);
  fault_pixel_ = kNoFault;
  // Pass 1 of a selected frame starts where pass 0 ended.
  timeline_.start(continues_frame() ? frame_.cycles : 0, continues_frame() ? frame_.timeline_slices : 0);
  out_ = {};
  out_.config = std::string(config_.name);
  out_.clock_mhz = config_.clock_mhz;
  out_.width = launch_.width;
  out_.height = launch_.height;
  out_.pixel_cycles.assign(pixels(), 0);
  out_.dram_bytes_per_cycle = config_.dram.bytes_per_cycle;
  lines_.emplace(*node_cache_, *triangle_cache_);
  progress_ = &progress;
  rounds_done_ = 0;
  rounds_total_ = (pixels() + static_cast<std::uint64_t>(config_.chunk_size) - 1) /
                  static_cast<std::uint64_t>(config_.chunk_size);

  const auto chunks_per_core = static_cast<std::uint32_t>(config_.threads_per_core / config_.chunk_size);
  const auto registers = static_cast<std::size_t>(config_.registers);
  walkers_ = config_.tu_pipe ? 1 : static_cast<std::uint32_t>(config_.tu_slots);
  events_.emplace(static_cast<std::size_t>(config_.shader_cores + config_.traversal_units) * walkers_);
  dispatch_.emplace(static_cast<std::size_t>(config_.shader_cores));
  cores_.clear();
  cores_.resize(static_cast<std::size_t>(config_.shader_cores));
  for (std::uint32_t c = 0; c < cores_.size(); ++c) {
    Core& core = cores_[c];
    core.data_cache = std::make_unique<Cache>(config_.data_cache, *dram_, line_wait);
    core.chunks.resize(chunks_per_core);
    for (std::uint32_t i = 0; i < chunks_per_core; ++i) {
      ChunkSlot& s = core.chunks[i];
      s.index = std::uint64_t{c} * chunks_per_core + i;
      s.core = c;
      s.reg_ready.assign(registers, 0);
      s.reg_rays.assign(registers, 0);
      start_round(c, i, 0);
    }
    plan(c, 0);
  }
  make_ray_units();

  {
    // One flush-to-zero scope for the frame's fp32 fast path, not one per step.
    const fp::fast32::FlushScope flush;
    const auto cores = static_cast<std::uint32_t>(cores_.size());
    while (const std::optional<EventQueue::Wakeup> e = events_->next()) {
      if (e->agent < cores) {
        core_event(e->agent, e->at);
      } else {
        wake_unit(e->agent - cores, units_[e->agent - cores]->advance(e->at));
      }
    }
  }
  const Cycle now = events_->now();
  const ShaderCore::Chunk* faulted = nullptr;
  for (const Core& core : cores_) {
    for (const ChunkSlot& s : core.chunks) {
      if (s.chunk.fault() && s.chunk.fault()->pixel() == fault_pixel_) faulted = &s.chunk;
    }
  }
  if (!faulted) {
    for (const Core& core : cores_) {
      for (const ChunkSlot& s : core.chunks) {
        if (s.live) throw Error(fmt::format("cycle model: no event left at cycle {} while chunk {} is live", now, s.index));
      }
    }
  }
  timeline_.flush();
  out_.timeline_slices = timeline_.slices();
  out_.timeline_cut_at = timeline_.cut_at();
  finish(now + 1);
  out_.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (continues_frame()) {
    frame_ += out_;
    stats_.shader += shader_stats_;
  } else {
    frame_ = out_;
    stats_.shader = shader_stats_;
  }
  stats_.host_threads = 1;
  stats_.host_seconds = frame_.host_seconds;
  stats_.report = report(frame_, stats_.shader);
  if (options_.frame_stats) options_.frame_stats(frame_);
  if (faulted) {
    const functional::ShaderFault fault = *faulted->fault();
    tracer_.reset();
    shader_.reset();
    throw fault;
  }
  tracer_.reset();
  shader_.reset();
}

// The totals, the idle time and the bounds of the frame that ended at `end`.
void CycleDevice::finish(Cycle end) {
  // The last lanes to enter a pipeline may do so after the last event.
  for (const Core& core : cores_) end = std::max(end, core.accounted);
  out_.cycles = end;
  for (Core& core : cores_) {
    core.wait = Wait::kIdle;
    account(core, end);
    out_.cores.push_back(core.time);
    out_.data_cache += core.data_cache->stats();
  }
  // A unit's times are its slots' summed: they add up to cycles x slots.
  out_.tu_slots = static_cast<std::uint32_t>(config_.tu_slots);
  out_.tus.assign(static_cast<std::size_t>(config_.traversal_units), TraversalUnitTime{});
  for (std::size_t u = 0; u < units_.size(); ++u) out_.tus[u / walkers_] += units_[u]->time(end);
  for (const IuTimer& iu : ius_) out_.ius.push_back(iu.time);
  out_.node_cache = node_cache_->stats();
  out_.triangle_cache = triangle_cache_->stats();
  out_.dram = dram_->stats();
  out_.closest_rays = shader_stats_.closest_rays;
  out_.any_rays = shader_stats_.any_rays;
  out_.thread_instructions = shader_stats_.instructions();

  // Speed of light: each resource's work at full rate, every access a hit, no queueing.
  const WalkCosts walk = WalkCosts::of(config_, layout_.isect_mode);
  const PipeCosts pipe = PipeCosts::of(config_, layout_.isect_mode);
  TraversalUnitTime tu_work;
  std::uint64_t tests = 0;
  for (const TraversalUnitTime& t : out_.tus) tu_work += t;
  for (const IntersectionUnitTime& t : out_.ius) tests += t.tests;
  const spec::TraversalUnitConfig& tc = config_.tu;
  const auto node_hit = static_cast<double>(config_.node_cache.hit_latency + config_.tu.memory_wait);
  const auto tri_hit = static_cast<double>(config_.triangle_cache.hit_latency + config_.tu.memory_wait);
  // A pipelined unit: its memory port moves a line a cycle (a node, a ref, a record's
  // lines), its set-up engines take `handoff` cycles a ray.
  const double pipe_cycles = std::max(
      static_cast<double>(tu_work.inner + tu_work.leaves + tu_work.refs + tu_work.tests * pipe.record_lines),
      static_cast<double>(tu_work.rays) * static_cast<double>(pipe.handoff) / config_.tu_setups);
  const double walk_cycles = static_cast<double>(tu_work.rays) * static_cast<double>(walk.setup) +
                           static_cast<double>(tu_work.inner) * (node_hit + tc.inner) +
                           static_cast<double>(tu_work.leaves) * (node_hit + tc.leaf) +
                           static_cast<double>(tu_work.refs) * tri_hit +
                           static_cast<double>(tu_work.tests) *
                               (tri_hit + static_cast<double>(walk.iu_latency + walk.iu_wait)) +
                           static_cast<double>(tu_work.pops) * tc.pop;
  out_.bounds = {
      // One lane a cycle enters a core's pipeline.
      {"shader cores (issue)", static_cast<double>(out_.thread_instructions) / config_.shader_cores},
      {"traversal units", config_.tu_pipe ? pipe_cycles / config_.traversal_units
                                          : walk_cycles / (config_.traversal_units * config_.tu_slots)},
      {"intersection units", static_cast<double>(tests) * static_cast<double>(walk.iu_interval) / config_.intersection_units},
      {"DRAM bus", static_cast<double>(out_.dram.bus_cycles)},
  };
  std::stable_sort(out_.bounds.begin(), out_.bounds.end(), [](const Bound& a, const Bound& b) { return a.cycles > b.cycles; });
}

}  // namespace

std::unique_ptr<device::Device> make_cycle_device(const spec::HardwareConfig& config, fp::Format format,
                                                  const CycleOptions& options) {
  return std::make_unique<CycleDevice>(config, format, options);
}

}  // namespace rpu::cycle
