#include "cycle/tu_pipe_timing.hpp"

#include <algorithm>
#include <bit>

#include "common/error.hpp"
#include "rpu/streams.hpp"

namespace rpu::cycle {

using functional::TraceEvent;

PipeCosts PipeCosts::of(const spec::HardwareConfig& config, IsectMode mode) {
  const bool watertight = mode == IsectMode::kWatertight;
  const spec::TraversalUnitConfig& tu = config.tu;
  PipeCosts c;
  c.slots = static_cast<std::uint32_t>(config.tu_slots);
  c.setups = static_cast<std::uint32_t>(config.tu_setups);
  c.handoff = static_cast<Cycle>(watertight ? tu.pipe_handoff_watertight : tu.pipe_handoff_woop);
  c.node = static_cast<Cycle>(tu.pipe_node);
  c.memory_wait = static_cast<Cycle>(tu.pipe_memory_wait);
  c.iu_latency = static_cast<Cycle>(watertight ? config.iu.watertight : config.iu.woop);
  c.iu_interval = static_cast<Cycle>(watertight ? config.iu.interval_watertight : config.iu.interval_woop);
  c.iu_wait = static_cast<Cycle>(tu.pipe_iu_wait);
  c.record_lines = isect_record_bytes(mode) / streams::kMemLineBytes;
  return c;
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

PipeTraversalUnit::PipeTraversalUnit(const PipeCosts& costs, LineSource& lines, std::span<IuTimer> ius)
    : costs_(costs), lines_(lines), ius_(ius), engines_(costs.setups), slots_(costs.slots) {
  if (costs.slots < 1 || costs.slots > 64 || costs.setups < 1 || costs.setups > 63 || ius.empty()) {
    throw Error("pipelined traversal unit: 1-64 slots, 1-63 set-up engines and an IU");
  }
  const auto rr = [](std::uint32_t inputs) { return RoundRobin{inputs, inputs - 1, 0, false}; };
  start_rr_ = rr(costs.setups);
  fetch_rr_ = ref_rr_ = pop_rr_ = fin_rr_ = rr(costs.slots);
  rsp_rr_ = rr(costs.setups + 1);
}

bool PipeTraversalUnit::ready() const {
  return std::any_of(engines_.begin(), engines_.end(), [](const Engine& e) { return !e.skid_valid; });
}

void PipeTraversalUnit::take(std::uint32_t ray, const functional::TraceLog& log) {
  incoming_ = {ray, &log};
  has_incoming_ = true;
  ++rays_;
}

void PipeTraversalUnit::tick(Cycle now, std::vector<std::uint32_t>& answered) {
  // --- This cycle's events, each decided on the state at its start (as the RTL's
  // combinational logic reads its registers). ---
  std::uint64_t offering = 0, missing = 0;  // engines offering a set-up ray, answering a miss
  for (std::size_t e = 0; e < engines_.size(); ++e) {
    const Engine& g = engines_[e];
    if (g.working && now >= g.offer_at) (g.ray.log->events.empty() ? missing : offering) |= std::uint64_t{1} << e;
  }
  std::uint64_t free = 0, ready = 0, leaf_end = 0, done = 0, refs = 0, leaf_over = 0;
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    Slot& sl = slots_[s];
    const std::uint64_t bit = std::uint64_t{1} << s;
    switch (sl.phase) {
      case Phase::kFree: free |= bit; continue;
      case Phase::kReady: ready |= bit; ++time.wait_memory; break;
      case Phase::kNode: ++(sl.stepping ? time.busy : time.wait_memory); break;
      case Phase::kLeaf:
        ++time.wait_iu;
        // Any refs left; an any-hit ray fetches one at a time.
        if (sl.k != sl.count && (sl.ray.log->mode != functional::TraceMode::kAny || sl.pending == 0)) refs |= bit;
        if (sl.pending == 0 && sl.k == sl.count) leaf_over |= bit;
        break;
      case Phase::kLeafEnd: leaf_end |= bit; ++time.busy; break;
      case Phase::kDone: done |= bit; ++time.busy; break;
      default: ++time.busy; break;
    }
  }

  const int start = start_rr_.grant(offering);
  start_rr_.update(start, free != 0);
  const bool give = start >= 0 && free != 0;

  // The memory port: a record line, else a ref, else a node.
  const std::size_t order_depth = costs_.slots + costs_.leaf_depth * (1 + costs_.record_lines);
  const bool go = order_.size() < (costs_.port_lines ? std::min<std::size_t>(order_depth, costs_.port_lines) : order_depth);
  const Kind source = !jobs_.empty() ? Kind::kRecord
                      : refs != 0 && work_ < costs_.leaf_depth ? Kind::kRef
                                                               : Kind::kNode;
  const int ref = ref_rr_.grant(refs);
  ref_rr_.update(ref, go && source == Kind::kRef);
  const bool ref_issue = ref >= 0 && go && source == Kind::kRef && work_ < costs_.leaf_depth;
  const int fetch = fetch_rr_.grant(ready);
  fetch_rr_.update(fetch, go && source == Kind::kNode);
  const bool fetched = fetch >= 0 && go && source == Kind::kNode;
  const bool record_go = go && source == Kind::kRecord;

  // The line answered, in order; a record line waits while the last record is whole.
  const bool line_taken = !order_.empty() && order_.front().at <= now &&
                          (order_.front().kind != Kind::kRecord || got_ < costs_.record_lines);
  const Line line = line_taken ? order_.front() : Line{};
  const bool inner_in = line_taken && line.kind == Kind::kNode && !line.leaf;

  const int pop = pop_rr_.grant(leaf_end);
  pop_rr_.update(pop, !inner_in);
  const bool pop_enter = pop >= 0 && !inner_in;

  IuTimer* iu = &*std::min_element(ius_.begin(), ius_.end(), [](const IuTimer& a, const IuTimer& b) {
    return a.next_accept < b.next_accept;
  });
  const bool test_issue = got_ == costs_.record_lines && !flight_.empty() && tests_busy_ < costs_.tests &&
                          iu->next_accept <= now;
  const bool answer = !answers_.empty() && answers_.top().at <= now;
  const bool decide = !steps_.empty() && steps_.front().at == now;

  const std::uint64_t out_valid = (fin_valid_ ? 1u : 0u) | missing << 1;
  const int rsp = rsp_rr_.grant(out_valid);
  rsp_rr_.update(rsp, true);
  const bool fin_rsp_taken = rsp == 0;
  const bool fin_ready = !fin_valid_ || fin_rsp_taken;
  const int fin = fin_rr_.grant(done);
  fin_rr_.update(fin, fin_ready);
  const bool fin_take = fin >= 0 && fin_ready;

  // --- The state at the cycle's end. ---
  // A ray taken goes to the lowest engine whose buffer has room (rpu_skid_buf's ready).
  std::size_t push_to = engines_.size();
  if (has_incoming_) {
    push_to = static_cast<std::size_t>(
        std::find_if(engines_.begin(), engines_.end(), [](const Engine& g) { return !g.skid_valid; }) -
        engines_.begin());
    if (push_to == engines_.size()) throw Error("pipelined traversal unit: a ray taken with no buffer free");
    has_incoming_ = false;
  }
  for (std::size_t e = 0; e < engines_.size(); ++e) {
    Engine& g = engines_[e];
    const bool takes = !g.working && g.out_valid;
    const bool missed = rsp == static_cast<int>(e) + 1;
    if ((give && start == static_cast<int>(e)) || missed) {
      g.working = false;
      ++time.rays;
      if (missed) {
        answered.push_back(g.ray.id);
        --rays_;
      }
    }
    if (takes) {
      g.working = true;
      g.ray = g.out;
      g.offer_at = now + costs_.handoff;
    }
    const bool push = e == push_to;
    if (takes || !g.out_valid) {
      g.out_valid = g.skid_valid || push;
      g.out = g.skid_valid ? g.skid : incoming_;
      g.skid_valid = g.skid_valid && push;
      g.skid = incoming_;
    } else if (push) {
      g.skid_valid = true;
      g.skid = incoming_;
    }
  }

  if (give) {
    Slot& sl = slots_[static_cast<std::size_t>(std::countr_zero(free))];
    sl = Slot{};
    sl.phase = Phase::kReady;
    sl.ray = engines_[static_cast<std::size_t>(start)].ray;
  }
  if (fetched) {
    Slot& sl = slots_[static_cast<std::size_t>(fetch)];
    const TraceEvent e = sl.ray.log->events[sl.next++];
    sl.phase = Phase::kNode;
    order_.push_back({lines_.read(now, e.address, spec::memory::kKdNodeBytes, true) + costs_.memory_wait,
                      Kind::kNode, e.kind == TraceEvent::Kind::kLeaf, static_cast<std::uint32_t>(fetch), 0});
  }
  if (ref_issue) {
    Slot& sl = slots_[static_cast<std::size_t>(ref)];
    const std::size_t i = sl.refs + 2 * sl.k;
    ++sl.k;
    ++sl.pending;
    ++work_;
    ++time.refs;
    const std::uint32_t address = sl.ray.log->events[i].address;
    order_.push_back({lines_.read(now, address, spec::memory::kPrimRefBytes, false) + costs_.memory_wait, Kind::kRef,
                      false, static_cast<std::uint32_t>(ref), sl.ray.log->events[i + 1].address});
  }
  if (record_go) {
    const Job job = jobs_.front();
    const std::uint32_t address = job.record + sent_ * streams::kMemLineBytes;
    order_.push_back({lines_.read(now, address, streams::kMemLineBytes, false) + costs_.memory_wait, Kind::kRecord,
                      false, job.slot, 0});
    if (++sent_ == costs_.record_lines) {
      sent_ = 0;
      flight_.push_back(job);
      jobs_.pop_front();
    }
  }
  if (line_taken) {
    order_.pop_front();
    Slot& sl = slots_[line.slot];
    switch (line.kind) {
      case Kind::kNode:
        if (line.leaf) {
          const auto& events = sl.ray.log->events;
          sl.phase = Phase::kLeaf;
          sl.refs = sl.next;
          sl.k = 0;
          sl.count = 0;
          while (sl.next < events.size() && events[sl.next].kind == TraceEvent::Kind::kRef) {
            sl.next += 2;
            ++sl.count;
          }
          ++time.leaves;
        } else {
          sl.stepping = true;
          steps_.push_back({now + costs_.node - 1, line.slot, false});
          ++time.inner;
        }
        break;
      case Kind::kRef: jobs_.push_back({line.slot, line.record}); break;
      case Kind::kRecord: ++got_; break;
    }
  }
  if (test_issue) {
    const Job job = flight_.front();
    flight_.pop_front();
    got_ = 0;
    ++tests_busy_;
    --work_;
    iu->next_accept = now + costs_.iu_interval;
    ++iu->time.tests;
    iu->time.busy += costs_.iu_interval;
    answers_.push({now + costs_.iu_latency + costs_.iu_wait, job.slot});
    ++time.tests;
  }
  if (answer) {
    --slots_[answers_.top().slot].pending;
    answers_.pop();
    --tests_busy_;
  }
  for (std::uint64_t m = leaf_over; m; m &= m - 1) slots_[static_cast<std::size_t>(std::countr_zero(m))].phase = Phase::kLeafEnd;
  if (pop_enter) {
    slots_[static_cast<std::size_t>(pop)].phase = Phase::kPop;
    steps_.push_back({now + costs_.node - 1, static_cast<std::uint32_t>(pop), true});
  }
  if (decide) {
    const Step step = steps_.front();
    steps_.pop_front();
    Slot& sl = slots_[step.slot];
    const auto& events = sl.ray.log->events;
    sl.stepping = false;
    if (step.pop) {
      for (; sl.next < events.size() && events[sl.next].kind == TraceEvent::Kind::kPop; ++sl.next) ++time.pops;
    }
    sl.phase = sl.next < events.size() ? Phase::kReady : Phase::kDone;
  }
  if (fin_rsp_taken) {
    Slot& sl = slots_[fin_slot_];
    sl.phase = Phase::kFree;
    answered.push_back(sl.ray.id);
    --rays_;
  }
  if (fin_take) {
    slots_[static_cast<std::size_t>(fin)].phase = Phase::kFinish;
    fin_slot_ = static_cast<std::uint32_t>(fin);
  }
  fin_valid_ = fin_take || (fin_valid_ && !fin_rsp_taken);
}

}  // namespace rpu::cycle
