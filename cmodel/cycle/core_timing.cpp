#include "cycle/core_timing.hpp"

#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "rpu/streams.hpp"

namespace rpu::cycle {

namespace si = spec::isa;
using isa::Opcode;

CoreTiming::CoreTiming(std::uint32_t index, const spec::HardwareConfig& config, functional::ShaderCore& shader,
                       functional::ShaderStats& stats, Dram& dram, EventQueue& events, Timeline& timeline, Chip& chip)
    : index_(index),
      config_(config),
      shader_(shader),
      stats_(stats),
      data_cache_(config.data_cache, dram, static_cast<Cycle>(config.latency.line_wait)),
      events_(events),
      timeline_(timeline),
      chip_(chip),
      track_(fmt::format("core {}", index)),
      chunks_(static_cast<std::size_t>(config.threads_per_core / config.chunk_size)),
      sfu_free_(static_cast<std::size_t>(config.sfu_threads), 0),
      sfu_busy_(sfu_free_.size(), 0),
      sfu_queues_(sfu_free_.size()) {}

void CoreTiming::start() {
  const auto registers = static_cast<std::size_t>(config_.registers);
  for (std::uint32_t i = 0; i < chunks_.size(); ++i) {
    ChunkSlot& s = chunks_[i];
    s.index = std::uint64_t{index_} * chunks_.size() + i;
    s.reg_ready.assign(registers, 0);
    s.reg_rays.assign(registers, 0);
    start_round(i, 0, 0);
  }
  plan(0);
}

void CoreTiming::account(Cycle until) {
  if (until <= accounted_) return;
  const Cycle n = until - accounted_;
  switch (wait_) {
    case Wait::kIdle: time_.idle += n; break;
    case Wait::kTrace: time_.wait_trace += n; break;
    case Wait::kMemory: time_.wait_memory += n; break;
    case Wait::kDependency: time_.wait_dependency += n; break;
  }
  accounted_ = until;
}

// The first cycle the chunk's next instruction can issue (its sources and destination
// ready: an in-order scoreboard; room in the queue it hands its lanes to), or kNever
// while a ray it needs is in flight.
Cycle CoreTiming::ready_time(const ChunkSlot& s) const {
  if (!s.ready_known) {
    s.ready_at = compute_ready_time(s);
    s.ready_known = true;
  }
  return s.ready_at;
}

Cycle CoreTiming::compute_ready_time(const ChunkSlot& s) const {
  if (!s.live || s.halted || s.chunk.threads().front().lane.pixel > chip_.first_fault()) return kNever;
  Cycle t = s.earliest;
  const std::uint32_t pc = s.chunk.next_pc();
  if (!shader_.instruction(pc)) return t;  // the step will fault
  const isa::RegisterUse& use = shader_.register_use(pc);
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
  const auto room = static_cast<std::size_t>(streams::kUnitQueueChunks - 1) *
                    static_cast<std::size_t>(config_.chunk_size);
  const isa::Instruction& in = *shader_.instruction(pc);
  if (in.spec->cls == si::Class::kTrace && chip_.queued_rays(index_) > room) return kNever;
  // The queue is looked at in the cycle the chunk would issue: not before the core asks
  // nor before the sequencer is free.
  if (in.spec->cls == si::Class::kMem || in.opcode() == Opcode::kCalli) {
    t = lsu_queue_.room(std::max({t, asked_, seq_free_}), room);
  }
  if (in.spec->cls == si::Class::kSfu) {
    // Every sfu's queue has room (rpu_spu takes the least free).
    t = std::max({t, asked_, seq_free_});
    for (Cycle before = kNever; before != t;) {
      before = t;
      for (const UnitQueue& q : sfu_queues_) t = q.room(t, room);
    }
  }
  return t;
}

void CoreTiming::UnitQueue::add(Cycle s0, Cycle out) {
  while (!entries_.empty() && entries_.front().second <= s0) entries_.pop_front();
  entries_.emplace_back(s0 + 2, out);
}

Cycle CoreTiming::UnitQueue::room(Cycle t, std::size_t room) const {
  for (;;) {
    std::size_t queued = 0;
    Cycle next_out = kNever;
    for (const auto& [in, out] : entries_) {
      if (in <= t && t < out) {
        ++queued;
        next_out = std::min(next_out, out);
      }
    }
    if (queued <= room) return t;
    t = next_out;
  }
}

// Wakes the core for its next issue at or after `from`, and notes why it waits until
// then as the RTL's counters do (docs/chip.md "Statistics"): for its own pipeline while
// a live chunk has neither rays nor loads out, else for memory while one has loads out,
// else for rays.
void CoreTiming::plan(Cycle from) {
  asked_ = from;
  Cycle best = kNever;
  bool own = false, loads = false, rays = false;
  for (const ChunkSlot& s : chunks_) {
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
  wait_ = own ? Wait::kDependency : loads ? Wait::kMemory : rays ? Wait::kTrace : Wait::kIdle;
  if (best != kNever) events_.wake(index_, std::max({best, from, seq_free_}));
}

void CoreTiming::run(Cycle now) {
  account(now);
  asked_ = now;
  const auto n = static_cast<std::uint32_t>(chunks_.size());
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::uint32_t>((next_chunk_ + k) % n);
    if (ready_time(chunks_[i]) > now) continue;
    next_chunk_ = i + 1;
    for (ChunkSlot& other : chunks_) other.ready_known = false;
    // Busy from the issue to its last lane's S0 (the next issue may share that cycle).
    const Cycle last = issue(i, now);
    time_.busy += last + 1 - std::max(now, accounted_);
    accounted_ = last + 1;
    break;
  }
  plan(now + 1);
}

// The first S0 cycle from `at` that no other value handed back has taken.
Cycle CoreTiming::take_return_slot(Cycle at) {
  auto it = return_slots_.lower_bound(at);
  while (it != return_slots_.end() && *it == at) {
    ++at;
    ++it;
  }
  return_slots_.insert(it, at);
  return at;
}

// A lane's access (its S0 in `s0`) through the load/store unit: in program order, one
// piece a cycle onto the data cache's port. A load's data comes back through S0: returns
// that cycle (0 for a store).
Cycle CoreTiming::send_access(Cycle s0, const functional::MemoryAccess& a) {
  Cycle at = std::max(s0 + static_cast<Cycle>(config_.latency.to_unit), lsu_free_);
  if (a.store) {
    lsu_free_ = data_cache_.write(at, a.address, a.bytes) + 1;
    lsu_queue_.add(s0, lsu_free_);
    return 0;
  }
  // A load holds one of the unit's miss registers from its first piece until its data
  // takes S0 (rpu_spu_lsu's load slots); with none free it waits at the queue's head.
  load_slots_.erase(load_slots_.begin(), load_slots_.upper_bound(at));
  if (load_slots_.size() >= streams::kLsuLoadSlots) {
    at = *load_slots_.begin();
    load_slots_.erase(load_slots_.begin());
  }
  lsu_free_ = at + port_pieces(a.address, a.bytes);
  lsu_queue_.add(s0, lsu_free_);
  const Cycle back =
      take_return_slot(data_cache_.read(at, a.address, a.bytes) + static_cast<Cycle>(config_.latency.from_unit));
  load_slots_.insert(back + 1);
  return back;
}

void CoreTiming::set_result(ChunkSlot& s, int reg, Cycle ready) {
  const auto r = static_cast<std::size_t>(reg);
  // A register the configuration lacks faulted the step's lanes: no result to time.
  if (reg < 0 || r >= s.reg_ready.size()) return;
  s.reg_ready[r] = ready;
}

// The S0 cycles of the lanes standing at `pc`, from the cycle after `now`, in cycles no
// value handed back has taken: a group of issue_lanes lanes (lanes l with the same
// l / issue_lanes) a cycle for an instruction of spec/isa.toml [issue] (its opcode bits
// decide, as the RTL's sequencer reads them), else one lane a cycle.
void CoreTiming::enter_lanes(const ChunkSlot& s, std::uint32_t pc, Cycle now) {
  const auto opcode = static_cast<spec::isa::Opcode>(shader_.word(pc) & ((1u << spec::isa::kOpcodeField.width) - 1));
  const spec::isa::InsnSpec* insn = isa::find_insn(opcode);  // null past the code's end (word 0)
  const std::size_t group = insn && insn->at_once ? static_cast<std::size_t>(config_.issue_lanes) : 1;
  return_slots_.erase(return_slots_.begin(), return_slots_.upper_bound(now));
  lane_slots_.clear();
  auto taken = return_slots_.begin();
  Cycle at = now;
  std::optional<std::size_t> last_group;
  const auto next_free = [&] {
    for (++at; taken != return_slots_.end() && *taken == at; ++at) ++taken;
  };
  const std::vector<functional::ShaderCore::Thread>& threads = s.chunk.threads();
  for (std::size_t l = 0; l < threads.size(); ++l) {
    if (threads[l].done || threads[l].pc != pc) continue;
    if (l / group != last_group) {
      next_free();
      ++time_.issue_slots;
    }
    last_group = l / group;
    lane_slots_.push_back(at);
  }
  if (lane_slots_.empty()) {
    next_free();
    ++time_.issue_slots;
    lane_slots_.push_back(at);
  }
}

// Lane k's S0 cycle (the last lane's for lanes past those that entered).
Cycle CoreTiming::lane_slot(std::size_t lane) const { return lane_slots_[std::min(lane, lane_slots_.size() - 1)]; }

// A value handed back takes S0 before the sequencer's next lane (rpu_spu: a return has
// the first claim), including one an earlier lane of the same instruction sent: the
// lanes of a one-lane-a-cycle instruction after lane k move past the returns taken
// since enter_lanes placed them.
void CoreTiming::yield_to_returns(std::size_t lane) {
  for (std::size_t j = lane + 1; j < lane_slots_.size(); ++j) {
    Cycle at = std::max(lane_slots_[j], lane_slots_[j - 1] + 1);
    for (auto it = return_slots_.lower_bound(at); it != return_slots_.end() && *it == at; ++it) ++at;
    lane_slots_[j] = at;
  }
}

// Issues chunk i's next instruction; returns the S0 cycle of its last lane.
Cycle CoreTiming::issue(std::uint32_t i, Cycle now) {
  ChunkSlot& s = chunks_[i];
  const std::uint32_t pc = s.chunk.next_pc();
  enter_lanes(s, pc, now);
  shader_.step(s.chunk, stats_, &record_);
  if (const functional::ShaderFault* f = s.chunk.fault(); f && f->pixel() < chip_.first_fault()) {
    chip_.fault(f->pixel());
  }
  ++time_.chunk_issues;
  const auto reissue = static_cast<Cycle>(config_.latency.reissue);
  s.earliest = lane_slots_.back() + reissue;
  // A step whose every lane faulted at an illegal pc has no instruction to time. Its
  // timing may move its last lanes later (returns of its first lanes come first).
  if (record_.insn) time_issue(i, pc, now);
  const Cycle last = lane_slots_.back();
  seq_free_ = last;
  const Cycle next = std::max(s.earliest, last + reissue);
  if (!s.chunk.done()) {
    fetch(i, next, now);
  } else if (s.rays_in_flight) {
    s.halted = true;
  } else {
    start_round(i, next, now);
  }
  return last;
}

// When the results of the step just issued are ready, and the memory and rays it sends:
// lane k entered S0 in lane_slot(k); results pass the datapath (latency.result); loads,
// sfu operations and rays go to their unit latency.to_unit later, and their values come
// back through S0.
void CoreTiming::time_issue(std::uint32_t i, std::uint32_t pc, Cycle now) {
  ChunkSlot& s = chunks_[i];
  const isa::Instruction& in = *record_.insn;
  const isa::RegisterUse& use = shader_.register_use(pc);
  const auto result = static_cast<Cycle>(config_.latency.result);
  switch (in.spec->cls) {
    case si::Class::kFpu:
    case si::Class::kInt:
    case si::Class::kSpecial: set_result(s, use.dst, lane_slots_.back() + result); break;
    case si::Class::kSfu: set_result(s, use.dst, time_sfu(in) + result); break;
    case si::Class::kBranch: {
      // calli reads its target from the shader table, one read per lane; the chunk
      // picks its next pc when the last has come back.
      const Cycle back = send_accesses();
      s.earliest = std::max(s.earliest, back + static_cast<Cycle>(config_.latency.reissue));
      s.loads_back = std::max(s.loads_back, back);
      break;
    }
    case si::Class::kMem: {
      const Cycle back = send_accesses();
      const bool load = std::any_of(record_.accesses.begin(), record_.accesses.end(),
                                    [](const functional::MemoryAccess& a) { return !a.store; });
      if (load) {
        set_result(s, use.dst, back + result);
        s.loads_back = std::max(s.loads_back, back);
      }
      break;
    }
    case si::Class::kTrace: send_rays(i, use.dst); break;
  }
  if (timeline_.enabled()) timeline_.add(track_, fmt::format("chunk {}: {}", i, in.spec->mnemonic), now, now + 1);
  if (in.opcode() == Opcode::kHalt) {
    for (std::size_t l = 0; l < s.chunk.threads().size(); ++l) {
      if (record_.lanes >> l & 1) chip_.halted(s.chunk.threads()[l].lane.pixel, now + 1 - s.round_start);
    }
  }
}

// The sfu takes one thread's instruction at a time; each divider takes its share of the
// written lanes back to back, one cycle apart. Returns the cycle the last value is back
// in S0.
Cycle CoreTiming::time_sfu(const isa::Instruction& in) {
  const spec::LatencyConfig& lat = config_.latency;
  const auto units = static_cast<Cycle>(config_.sfu_units);
  const auto passes = (static_cast<Cycle>(std::popcount(in.wmask)) + units - 1) / units;
  const auto each = static_cast<Cycle>(in.opcode() == Opcode::kRsq ? lat.rsq : lat.sfu) + 1;
  Cycle done = 0;
  std::uint32_t lanes = record_.lanes;
  for (std::size_t k = 0; lanes != 0; ++k, lanes &= lanes - 1) {
    // The thread in chunk lane l goes to sfu l mod sfu_threads.
    const std::size_t unit = static_cast<std::size_t>(std::countr_zero(lanes)) % sfu_free_.size();
    const Cycle start = std::max(lane_slot(k) + static_cast<Cycle>(lat.to_unit), sfu_free_[unit]);
    // The value waits for S0; the next thread instruction starts once it has left.
    const Cycle back = take_return_slot(start + passes * each - 1 + static_cast<Cycle>(lat.from_unit));
    sfu_free_[unit] = back + 1;
    sfu_busy_[unit] += back + 1 - start;
    sfu_queues_[unit].add(lane_slot(k), back + 1);
    done = std::max(done, back);
    yield_to_returns(k);
  }
  return done;
}

// The step's memory accesses, lane by lane: the cycle the last load's data is back in
// S0 (0 without loads).
Cycle CoreTiming::send_accesses() {
  Cycle back = 0;
  for (std::size_t k = 0; k < record_.accesses.size(); ++k) {
    back = std::max(back, send_access(lane_slot(k), record_.accesses[k]));
    yield_to_returns(k);
  }
  return back;
}

// Each lane's ray goes to the dispatch latency.to_unit after its S0, for register `dst`.
void CoreTiming::send_rays(std::uint32_t i, int dst) {
  ChunkSlot& s = chunks_[i];
  for (std::size_t k = 0; k < record_.trace_count; ++k) {
    Ray ray;
    ray.core = index_;
    ray.chunk = i;
    ray.dst = static_cast<std::uint32_t>(dst);
    ray.packet_end = k + 1 == record_.trace_count;
    std::swap(ray.log, record_.traces[k]);
    if (!spare_logs_.empty()) {  // reuse an answered ray's storage
      std::swap(record_.traces[k], spare_logs_.back());
      spare_logs_.pop_back();
    }
    ++s.reg_rays[static_cast<std::size_t>(dst)];
    ++s.rays_in_flight;
    chip_.queue_ray(std::move(ray), lane_slot(k) + static_cast<Cycle>(config_.latency.to_unit));
  }
}

// Chunk i may issue from `ready` but for the code memory's one read port, which it
// reads two cycles before (rpu_spu's CFetch, CFetchWait): one chunk a cycle, the lowest
// first, so chunk i takes a cycle booked by a higher chunk and moves that one on.
// Bookings before `now` have happened and are forgotten.
void CoreTiming::fetch(std::uint32_t i, Cycle ready, Cycle now) {
  fetches_.erase(fetches_.begin(), fetches_.lower_bound(now));
  for (Cycle at = ready;; ++at) {
    auto [it, took] = fetches_.try_emplace(at, i);
    if (!took && it->second > i) std::swap(it->second, i), took = true;  // i now the one moved on
    if (!took) continue;
    ChunkSlot& s = chunks_[it->second];
    s.earliest = at;
    s.ready_known = false;
    if (it->second == i) return;
  }
}

// Chunk i's current round is over: it takes its next round of pixels, if any.
void CoreTiming::start_round(std::uint32_t i, Cycle at, Cycle now) {
  ChunkSlot& s = chunks_[i];
  s.ready_known = false;
  if (s.live) {
    chip_.round_done();
    ++s.round;
  }
  s.halted = false;
  chip_.round_lanes(s.round, s.index, lanes_);
  // A chunk that faulted keeps its fault: its next round's pixels all come after it.
  s.live = !lanes_.empty() && lanes_.front().pixel < chip_.first_fault();
  if (!s.live) return;
  shader_.start(s.chunk, lanes_, stats_);
  s.round_start = at;
  fetch(i, at, now);
  std::fill(s.reg_ready.begin(), s.reg_ready.end(), at);
}

// The answer enters the core's pipeline and is written like any result.
void CoreTiming::ray_answered(Ray& ray, Cycle now) {
  ChunkSlot& s = chunks_[ray.chunk];
  const auto dst = static_cast<std::size_t>(ray.dst);
  s.ready_known = false;
  const auto from_rays = static_cast<Cycle>(config_.tu_pipe ? config_.tu.pipe_from_unit : config_.latency.from_rays);
  const Cycle back = take_return_slot(now + from_rays) + static_cast<Cycle>(config_.latency.result);
  s.reg_ready[dst] = std::max(s.reg_ready[dst], back);
  --s.reg_rays[dst];
  --s.rays_in_flight;
  account(now);  // the wait so far had the old reason
  if (s.halted && !s.rays_in_flight) start_round(ray.chunk, back, now);
  plan(now + 1);
  spare_logs_.push_back(std::move(ray.log));
}

void CoreTiming::ray_dispatched(Cycle at) {
  forget_ready_times();
  plan(at);
}

void CoreTiming::forget_ready_times() {
  for (ChunkSlot& s : chunks_) s.ready_known = false;
}

ShaderCoreTime CoreTiming::finish(Cycle end) {
  wait_ = Wait::kIdle;
  account(end);
  time_.sfu_busy = *std::max_element(sfu_busy_.begin(), sfu_busy_.end());
  return time_;
}

const functional::ShaderFault* CoreTiming::fault_at(std::uint32_t pixel) const {
  for (const ChunkSlot& s : chunks_) {
    if (s.chunk.fault() && s.chunk.fault()->pixel() == pixel) return s.chunk.fault();
  }
  return nullptr;
}

std::optional<std::uint64_t> CoreTiming::live_chunk() const {
  for (const ChunkSlot& s : chunks_) {
    if (s.live) return s.index;
  }
  return std::nullopt;
}

}  // namespace rpu::cycle
