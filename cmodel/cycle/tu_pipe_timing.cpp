#include "cycle/tu_pipe_timing.hpp"

#include <algorithm>
#include <bit>

#include <fmt/format.h>

#include "common/error.hpp"
#include "rpu/streams.hpp"

namespace rpu::cycle {

using functional::TraceEvent;

PipeCosts PipeCosts::of(const spec::HardwareConfig& config, IsectMode mode) {
  const bool watertight = mode == IsectMode::kWatertight;
  const spec::TraversalUnitConfig& tu = config.tu;
  // A cache pair's arbiter takes log2(its units) of a read's tag bits: each unit keeps
  // as many lines in flight as the rest can name.
  const auto pair_units = static_cast<std::uint32_t>(config.traversal_units / config.ray_caches);
  const auto unit_bits = static_cast<std::uint32_t>(std::bit_width(pair_units - 1));
  return {
      .slots = static_cast<std::uint32_t>(config.tu_slots),
      .setups = static_cast<std::uint32_t>(config.tu_setups),
      .lines = 1u << (streams::kCacheTagBits - std::min(unit_bits, streams::kCacheTagBits)),
      .by_tag = config.tu_by_tag != 0,
      .handoff = static_cast<Cycle>(watertight ? tu.pipe_handoff_watertight : tu.pipe_handoff_woop),
      .node = static_cast<Cycle>(tu.pipe_node),
      .memory_wait = static_cast<Cycle>(config.tu_by_tag ? tu.pipe_memory_wait_by_tag : tu.pipe_memory_wait),
      .iu_latency = static_cast<Cycle>(watertight ? config.iu.watertight : config.iu.woop),
      .iu_interval = static_cast<Cycle>(watertight ? config.iu.interval_watertight : config.iu.interval_woop),
      .iu_wait = static_cast<Cycle>(tu.pipe_iu_wait),
      .record_lines = isect_record_bytes(mode) / streams::kMemLineBytes,
      .packet = static_cast<std::uint32_t>(config.tu_packet),
  };
}

int PipeTraversalUnit::RoundRobin::grant(std::uint64_t valid) const {
  if (hold && (valid >> held & 1)) return static_cast<int>(held);
  for (std::uint32_t k = 1; k <= inputs; ++k) {
    const std::uint32_t i = (last + k) % inputs;
    if (valid >> i & 1) return static_cast<int>(i);
  }
  return -1;
}

void PipeTraversalUnit::RoundRobin::update(int grant, bool ready) {
  if (grant >= 0 && ready) last = static_cast<std::uint32_t>(grant);
  hold = grant >= 0 && !ready;
  if (grant >= 0) held = static_cast<std::uint32_t>(grant);
}

PipeTraversalUnit::PipeTraversalUnit(const PipeCosts& costs, LineSource& lines, std::span<IuTimer> ius,
                                     PacketWalks* walks)
    : costs_(costs), lines_(lines), ius_(ius), walks_(walks), engines_(costs.setups), slots_(costs.slots),
      jobs_(kLeafDepth), buffers_(kRecords) {
  if (costs.slots < 1 || costs.slots > 64 || costs.setups < 1 || costs.setups > 63 || costs.lines < 1 || ius.empty()) {
    throw Error("pipelined traversal unit: 1-64 slots, 1-63 set-up engines, a line in flight and an IU");
  }
  if (costs.packet < 1 || costs.packet > functional::kMaxPacketRays || (costs.packet > 1 && !walks)) {
    throw Error(fmt::format("pipelined traversal unit: packets of 1 to {} rays, and with more than one their walks",
                            functional::kMaxPacketRays));
  }
  const auto rr = [](std::uint32_t inputs) { return RoundRobin{inputs, inputs - 1, 0, false}; };
  start_rr_ = rr(costs.setups);
  fetch_rr_ = ref_rr_ = pop_rr_ = fin_rr_ = rr(costs.slots);
  rsp_rr_ = rr(costs.setups + 1);
}

bool PipeTraversalUnit::ready() const {
  return std::any_of(engines_.begin(), engines_.end(), [](const Engine& e) { return !e.skid_valid; });
}

void PipeTraversalUnit::take(std::uint32_t ray, const functional::TraceLog& log, const PacketRay& packet) {
  incoming_ = {ray, &log, packet, in_seq_};
  has_incoming_ = true;
  end_taken_ = packet.packet_end;
  ++rays_;
}

// A cycle of the unit: each stage's grant is decided on the state at the cycle's start
// (as the RTL's combinational logic reads its registers), then each stage's registers
// take their values at the cycle's end.
void PipeTraversalUnit::tick(Cycle now, std::vector<std::uint32_t>& answered) {
  Grants g;
  const std::uint64_t offering = grant_engines(now, g);
  grant_slots(g);
  grant_start(offering, g);
  grant_port(g);
  grant_line(now, g);
  grant_pop(g);
  grant_test(now, g);
  grant_response(g);

  set_up(now, g, answered);
  fetch(now, g);
  take_line(now, g);
  test(now, g);
  pop(now, g);
  step(g);
  respond(g, answered);
  if (end_taken_) ++in_seq_;
  end_taken_ = false;
}

// Set-up engines: those offering a set-up ray to the slots, or answering a ray that
// misses the scene box (grants.missing).
std::uint64_t PipeTraversalUnit::grant_engines(Cycle now, Grants& g) const {
  std::uint64_t offering = 0;
  for (std::size_t e = 0; e < engines_.size(); ++e) {
    const Engine& en = engines_[e];
    if (en.working && now >= en.offer_at) (en.ray.log->events.empty() ? g.missing : offering) |= std::uint64_t{1} << e;
  }
  return offering;
}

// The slots by phase, and their cycle in the unit's time.
void PipeTraversalUnit::grant_slots(Grants& g) {
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    const Slot& sl = slots_[s];
    const std::uint64_t bit = std::uint64_t{1} << s;
    switch (sl.phase) {
      case Phase::kFree: g.free |= bit; continue;
      case Phase::kReady: g.ready |= bit; ++time.wait_memory; break;
      case Phase::kNode: ++(sl.stepping ? time.busy : time.wait_memory); break;
      case Phase::kLeaf:
        ++time.wait_iu;
        // Any refs left; an any-hit ray fetches one at a time.
        if (sl.k != sl.count && (sl.log->mode != functional::TraceMode::kAny || sl.pending == 0)) g.refs |= bit;
        if (sl.pending == 0 && sl.k == sl.count) g.leaf_over |= bit;
        break;
      case Phase::kLeafEnd: g.leaf_end |= bit; ++time.busy; break;
      case Phase::kDone: g.done |= bit; ++time.busy; break;
      default: ++time.busy; break;
    }
  }
}

// A slot takes an offered ray: the packet being formed, if the ray came in the same
// input packet with the same signs and mode and the packet has room, else a free slot.
// The packet being formed closes when another opens, or no ray of its input packet is
// left in set-up and the input has moved past it.
void PipeTraversalUnit::grant_start(std::uint64_t offering, Grants& g) {
  g.start = start_rr_.grant(offering);
  if (g.start >= 0 && costs_.packet > 1 && form_open_) {
    const Ray& r = engines_[static_cast<std::size_t>(g.start)].ray;
    g.join = r.seq == form_seq_ && r.packet.signs == form_signs_ && r.packet.any_hit == form_any_hit_ &&
             slots_[form_slot_].rays.size() != costs_.packet;
  }
  const bool ready = g.join || g.free != 0;
  start_rr_.update(g.start, ready);
  g.give = g.start >= 0 && ready;
  g.form_ends = form_open_ && forming_ends();
  g.close_formed = form_open_ && ((g.give && !g.join) || g.form_ends);
}

// No ray of the packet being formed's input packet is in set-up, and the input has
// moved past it.
bool PipeTraversalUnit::forming_ends() const {
  if (in_seq_ == form_seq_) return false;
  return std::none_of(engines_.begin(), engines_.end(), [&](const Engine& en) {
    return (en.working && en.ray.seq == form_seq_) || (en.out_valid && en.out.seq == form_seq_) ||
           (en.skid_valid && en.skid.seq == form_seq_);
  });
}

// A packet closes: its walk (the ray's own alone), and it walks from the next cycle.
void PipeTraversalUnit::close(Slot& sl) {
  sl.phase = Phase::kReady;
  if (costs_.packet > 1) {
    sl.walk.events.clear();
    walks_->walk(sl.rays, sl.walk);
    sl.log = &sl.walk;
  }
}

// The memory port takes a record line (of the job being read, or the lowest job that is
// its slot's next record, while a record buffer is free), else a ref, else a node,
// while the line table has room.
void PipeTraversalUnit::grant_port(Grants& g) {
  const bool go = order_.size() < costs_.lines;
  const bool buffer_free = std::any_of(buffers_.begin(), buffers_.end(), [](const RecordBuffer& b) { return !b.busy; });
  g.job = sent_ != 0 ? static_cast<int>(send_job_) : -1;
  for (std::size_t j = 0; j < jobs_.size() && (g.job < 0 || g.job_free < 0); ++j) {
    const Job& job = jobs_[j];
    if (g.job < 0 && job.busy && job.k == slots_[job.slot].rec_k) g.job = static_cast<int>(j);
    if (g.job_free < 0 && !job.busy) g.job_free = static_cast<int>(j);
  }
  const Kind source = g.job >= 0 && (sent_ != 0 || buffer_free) ? Kind::kRecord
                      : g.refs != 0 && work_ < kLeafDepth ? Kind::kRef
                                                                 : Kind::kNode;
  g.ref = ref_rr_.grant(g.refs);
  ref_rr_.update(g.ref, go && source == Kind::kRef);
  g.ref_issue = g.ref >= 0 && go && source == Kind::kRef && work_ < kLeafDepth;
  g.fetch = fetch_rr_.grant(g.ready);
  fetch_rr_.update(g.fetch, go && source == Kind::kNode);
  g.fetched = g.fetch >= 0 && go && source == Kind::kNode;
  g.record_go = go && source == Kind::kRecord;
}

// The line answered, one a cycle: the oldest, once it is back (in order); or the first
// back, the oldest of those back together (by tag).
void PipeTraversalUnit::grant_line(Cycle now, Grants& g) const {
  g.line_taken = false;
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const Line& l = order_[i];
    if (l.at <= now && (!g.line_taken || l.at < g.line.at)) {
      g.line_taken = true;
      g.line_at = i;
      g.line = l;
    }
    if (!costs_.by_tag) break;
  }
}

// The record buffer whose record goes to the IU next: the one whose tests have begun,
// else the lowest whole one that is its slot's next test (-1: none).
int PipeTraversalUnit::whole_buffer() const {
  if (test_hold_) return static_cast<int>(test_held_);
  for (std::size_t b = 0; b < buffers_.size(); ++b) {
    const RecordBuffer& r = buffers_[b];
    if (r.busy && r.got == costs_.record_lines && r.job.k == slots_[r.job.slot].test_k) return static_cast<int>(b);
  }
  return -1;
}

// A finished leaf's pop pass enters the node-step pipeline in a cycle no inner node's
// line does.
void PipeTraversalUnit::grant_pop(Grants& g) {
  const bool inner_in = g.line_taken && g.line.kind == Kind::kNode && !g.line.leaf;
  g.pop = pop_rr_.grant(g.leaf_end);
  pop_rr_.update(g.pop, !inner_in);
  g.pop_enter = g.pop >= 0 && !inner_in;
}

// A whole record goes to the IU free first; an IU answer comes back; a node step
// decides.
void PipeTraversalUnit::grant_test(Cycle now, Grants& g) {
  g.iu = &*std::min_element(ius_.begin(), ius_.end(),
                            [](const IuTimer& a, const IuTimer& b) { return a.next_accept < b.next_accept; });
  g.test_buffer = whole_buffer();
  g.test_issue = g.test_buffer >= 0 && tests_busy_ < kTests && g.iu->next_accept <= now;
  g.answer = !answers_.empty() && answers_.top().at <= now;
  g.decide = !steps_.empty() && steps_.front().at == now;
}

// The response arbiter: the finish stage's ray or an engine's miss leaves; the finish
// stage takes a done slot when its ray leaves or it holds none.
void PipeTraversalUnit::grant_response(Grants& g) {
  const std::uint64_t out_valid = (fin_valid_ ? 1u : 0u) | g.missing << 1;
  g.rsp = rsp_rr_.grant(out_valid);
  rsp_rr_.update(g.rsp, true);
  g.fin_rsp_taken = g.rsp == 0;
  // A packet's rays leave one a cycle; the stage is free when its last has.
  const bool fin_last = fin_valid_ && slots_[fin_slot_].answered + 1 == slots_[fin_slot_].rays.size();
  const bool fin_ready = !fin_valid_ || (g.fin_rsp_taken && fin_last);
  g.fin = fin_rr_.grant(g.done);
  fin_rr_.update(g.fin, fin_ready);
  g.fin_take = g.fin >= 0 && fin_ready;
}

// The engine whose buffer takes the ray taken this cycle: the lowest with room
// (rpu_skid_buf's ready); none (engines_.size()) without a ray.
std::size_t PipeTraversalUnit::incoming_engine() {
  if (!has_incoming_) return engines_.size();
  has_incoming_ = false;
  const auto e = static_cast<std::size_t>(
      std::find_if(engines_.begin(), engines_.end(), [](const Engine& en) { return !en.skid_valid; }) -
      engines_.begin());
  if (e == engines_.size()) throw Error("pipelined traversal unit: a ray taken with no buffer free");
  return e;
}

// The set-up engines: the ray taken enters a buffer, an engine takes its buffer's ray,
// hands a set-up ray to a free slot or answers a miss.
void PipeTraversalUnit::set_up(Cycle now, const Grants& g, std::vector<std::uint32_t>& answered) {
  const std::size_t push_to = incoming_engine();
  for (std::size_t e = 0; e < engines_.size(); ++e) {
    Engine& en = engines_[e];
    const bool takes = !en.working && en.out_valid;
    const bool missed = g.rsp == static_cast<int>(e) + 1;
    if ((g.give && g.start == static_cast<int>(e)) || missed) {
      en.working = false;
      ++time.rays;
      if (missed) {
        answered.push_back(en.ray.id);
        --rays_;
      }
    }
    if (takes) {
      en.working = true;
      en.ray = en.out;
      en.offer_at = now + costs_.handoff;
    }
    const bool push = e == push_to;
    if (takes || !en.out_valid) {
      en.out_valid = en.skid_valid || push;
      en.out = en.skid_valid ? en.skid : incoming_;
      en.skid_valid = en.skid_valid && push;
      en.skid = incoming_;
    } else if (push) {
      en.skid_valid = true;
      en.skid = incoming_;
    }
  }
  const std::uint32_t formed = form_slot_;
  if (g.give) {
    const Ray& ray = engines_[static_cast<std::size_t>(g.start)].ray;
    const std::uint32_t s = g.join ? form_slot_ : static_cast<std::uint32_t>(std::countr_zero(g.free));
    Slot& sl = slots_[s];
    if (!g.join) {
      sl.phase = Phase::kForm;
      sl.ray = ray;
      sl.rays.clear();
      sl.log = ray.log;
      sl.answered = 0;
      sl.next = sl.refs = 0;
      sl.count = sl.k = sl.pending = sl.rec_k = sl.test_k = 0;
      sl.stepping = false;
    }
    sl.rays.push_back(ray.id);
    const bool full = sl.rays.size() == costs_.packet;
    if (full) close(sl);
    form_open_ = !full;
    form_slot_ = s;
    form_seq_ = ray.seq;
    form_signs_ = ray.packet.signs;
    form_any_hit_ = ray.packet.any_hit;
  } else if (g.form_ends) {
    form_open_ = false;
  }
  if (g.close_formed) close(slots_[formed]);
}

// The memory port: a slot's node line, a leaf's prim ref, or a record's next line.
void PipeTraversalUnit::fetch(Cycle now, const Grants& g) {
  if (g.fetched) {
    Slot& sl = slots_[static_cast<std::size_t>(g.fetch)];
    const TraceEvent e = sl.log->events[sl.next++];
    sl.phase = Phase::kNode;
    order_.push_back({lines_.read(now, e.address, spec::memory::kKdNodeBytes, true) + costs_.memory_wait,
                      Kind::kNode, e.kind == TraceEvent::Kind::kLeaf, static_cast<std::uint32_t>(g.fetch), 0});
  }
  if (g.ref_issue) {
    Slot& sl = slots_[static_cast<std::size_t>(g.ref)];
    const std::size_t i = sl.refs + 2 * sl.k;
    const TraceEvent& test = sl.log->events[i + 1];
    ++sl.k;
    sl.pending += test.rays;
    ++work_;
    ++time.refs;
    const std::uint32_t address = sl.log->events[i].address;
    order_.push_back({lines_.read(now, address, spec::memory::kPrimRefBytes, false) + costs_.memory_wait, Kind::kRef,
                      false, static_cast<std::uint32_t>(g.ref), test.address, sl.k - 1, test.rays});
  }
  if (g.record_go) {
    const Job job = jobs_[static_cast<std::size_t>(g.job)];
    if (sent_ == 0) {
      send_job_ = static_cast<std::uint32_t>(g.job);
      fill_buffer_ = static_cast<std::uint32_t>(
          std::find_if(buffers_.begin(), buffers_.end(), [](const RecordBuffer& b) { return !b.busy; }) -
          buffers_.begin());
      buffers_[fill_buffer_] = {true, 0, job, 0};
    }
    const std::uint32_t address = job.record + sent_ * streams::kMemLineBytes;
    order_.push_back({lines_.read(now, address, streams::kMemLineBytes, false) + costs_.memory_wait, Kind::kRecord,
                      false, job.slot, fill_buffer_});
    if (++sent_ == costs_.record_lines) {
      sent_ = 0;
      jobs_[send_job_].busy = false;
      ++slots_[job.slot].rec_k;
    }
  }
}

// The line answered: a leaf's refs counted, an inner node into the node-step pipeline,
// a ref's record queued, a record line kept.
void PipeTraversalUnit::take_line(Cycle now, const Grants& g) {
  if (!g.line_taken) return;
  order_.erase(order_.begin() + static_cast<std::ptrdiff_t>(g.line_at));
  Slot& sl = slots_[g.line.slot];
  switch (g.line.kind) {
    case Kind::kNode:
      if (g.line.leaf) {
        const auto& events = sl.log->events;
        sl.phase = Phase::kLeaf;
        sl.refs = sl.next;
        sl.k = 0;
        sl.count = 0;
        sl.rec_k = sl.test_k = 0;
        while (sl.next < events.size() && events[sl.next].kind == TraceEvent::Kind::kRef) {
          sl.next += 2;
          ++sl.count;
        }
        ++time.leaves;
      } else {
        sl.stepping = true;
        steps_.push_back({now + costs_.node - 1, g.line.slot, false});
        ++time.inner;
      }
      break;
    case Kind::kRef:
      if (g.job_free < 0) throw Error("pipelined traversal unit: a ref answered with the job table full");
      jobs_[static_cast<std::size_t>(g.job_free)] = {true, g.line.slot, g.line.k, g.line.record, g.line.tests};
      break;
    case Kind::kRecord: ++buffers_[g.line.record].got; break;
  }
}

// The leaf's tests: a record to the IU, an answer back, a leaf whose tests are all
// answered ends.
void PipeTraversalUnit::test(Cycle now, const Grants& g) {
  if (g.test_issue) {
    // A record goes to the IU once per ray of its packet that tests it, one a cycle.
    RecordBuffer& buffer = buffers_[static_cast<std::size_t>(g.test_buffer)];
    const Job job = buffer.job;
    const bool last = ++buffer.sent == job.tests;
    test_hold_ = !last;
    test_held_ = static_cast<std::uint32_t>(g.test_buffer);
    if (last) {
      buffer.busy = false;
      ++slots_[job.slot].test_k;
      --work_;
    }
    ++tests_busy_;
    g.iu->next_accept = now + costs_.iu_interval;
    ++g.iu->time.tests;
    g.iu->time.busy += costs_.iu_interval;
    answers_.push({now + costs_.iu_latency + costs_.iu_wait, job.slot});
    ++time.tests;
  }
  if (g.answer) {
    --slots_[answers_.top().slot].pending;
    answers_.pop();
    --tests_busy_;
  }
  for (std::uint64_t m = g.leaf_over; m; m &= m - 1) {
    slots_[static_cast<std::size_t>(std::countr_zero(m))].phase = Phase::kLeafEnd;
  }
}

// A finished leaf's pop pass enters the node-step pipeline.
void PipeTraversalUnit::pop(Cycle now, const Grants& g) {
  if (!g.pop_enter) return;
  slots_[static_cast<std::size_t>(g.pop)].phase = Phase::kPop;
  steps_.push_back({now + costs_.node - 1, static_cast<std::uint32_t>(g.pop), true});
}

// The node step's decide stage: the slot's pops done, it fetches its next node or is
// done.
void PipeTraversalUnit::step(const Grants& g) {
  if (!g.decide) return;
  const Step s = steps_.front();
  steps_.pop_front();
  Slot& sl = slots_[s.slot];
  const auto& events = sl.log->events;
  sl.stepping = false;
  if (s.pop && costs_.packet > 1) {
    // A packet's pass pops one entry; it passes again while the entry woke no ray.
    ++sl.next;
    ++time.pops;
    if (sl.next < events.size() && events[sl.next].kind == TraceEvent::Kind::kPop) {
      sl.phase = Phase::kLeafEnd;
      return;
    }
  } else if (s.pop) {
    for (; sl.next < events.size() && events[sl.next].kind == TraceEvent::Kind::kPop; ++sl.next) ++time.pops;
  }
  sl.phase = sl.next < events.size() ? Phase::kReady : Phase::kDone;
}

// The finish stage's ray leaves through the response arbiter, its slot frees, and the
// stage takes the next done slot.
void PipeTraversalUnit::respond(const Grants& g, std::vector<std::uint32_t>& answered) {
  bool fin_done = false;
  if (g.fin_rsp_taken) {
    Slot& sl = slots_[fin_slot_];
    answered.push_back(sl.rays[sl.answered++]);
    --rays_;
    fin_done = sl.answered == sl.rays.size();
    if (fin_done) sl.phase = Phase::kFree;
  }
  if (g.fin_take) {
    slots_[static_cast<std::size_t>(g.fin)].phase = Phase::kFinish;
    fin_slot_ = static_cast<std::uint32_t>(g.fin);
  }
  fin_valid_ = g.fin_take || (fin_valid_ && !fin_done);
}

Cycle PipeUnitTiming::advance(Cycle now) {
  if (unit_.ready()) {
    if (std::optional<Ray> ray = ports_.send_ray(now, index_)) {
      if (free_ids_.empty()) {
        free_ids_.push_back(static_cast<std::uint32_t>(rays_.size()));
        rays_.emplace_back();
      }
      const std::uint32_t id = free_ids_.back();
      free_ids_.pop_back();
      rays_[id] = std::move(*ray);
      rays_[id].taken = now;
      const functional::TraceLog& log = rays_[id].log;
      unit_.take(id, log,
                 {rays_[id].packet_end, packet_ > 1 ? tracer_->direction_signs(log.ray) : 0,
                  log.mode == functional::TraceMode::kAny});
    }
  }
  answered_.clear();
  unit_.tick(now, answered_);
  for (const std::uint32_t id : answered_) {
    ports_.answer(rays_[id], now);
    free_ids_.push_back(id);
  }
  return !unit_.idle() || ports_.rays_waiting() ? now + 1 : kNever;
}

void PipeUnitTiming::walk(std::span<const std::uint32_t> rays, functional::TraceLog& log) {
  packet_rays_.clear();
  for (const std::uint32_t id : rays) packet_rays_.push_back(rays_[id].log.ray);
  out_.resize(packet_rays_.size());
  tracer_->trace_packet(packet_rays_, rays_[rays[0]].log.mode, out_, log);
}

TraversalUnitTime PipeUnitTiming::time(Cycle end) const {
  TraversalUnitTime t = unit_.time;
  const Cycle slot_cycles = end * slots_;
  t.idle = slot_cycles - std::min(slot_cycles, t.busy + t.wait_memory + t.wait_iu);
  return t;
}

}  // namespace rpu::cycle
