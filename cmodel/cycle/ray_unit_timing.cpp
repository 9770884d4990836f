#include "cycle/ray_unit_timing.hpp"

#include <algorithm>

namespace rpu::cycle {

using functional::TraceEvent;

WalkCosts WalkCosts::of(const spec::HardwareConfig& config, IsectMode mode) {
  const bool watertight = mode == IsectMode::kWatertight;
  const spec::TraversalUnitConfig& tu = config.tu;
  return {
      .setup = static_cast<Cycle>(watertight ? tu.setup_watertight : tu.setup_woop),
      .inner = static_cast<Cycle>(tu.inner),
      .leaf = static_cast<Cycle>(tu.leaf),
      .pop = static_cast<Cycle>(tu.pop),
      .memory_wait = static_cast<Cycle>(tu.memory_wait),
      .iu_wait = static_cast<Cycle>(tu.iu_wait),
      .turnaround = static_cast<Cycle>(tu.turnaround),
      .iu_latency = static_cast<Cycle>(watertight ? config.iu.watertight : config.iu.woop),
      .iu_interval = static_cast<Cycle>(watertight ? config.iu.interval_watertight : config.iu.interval_woop),
      .record_bytes = isect_record_bytes(mode),
  };
}

WalkStep step_walk(const functional::TraceLog& log, Walk& walk, Cycle now, const WalkCosts& costs,
                   LineSource& memory, std::span<IuTimer> ius, TraversalUnitTime& time) {
  WalkStep step;
  if (!walk.set_up) {
    walk.set_up = true;
    time.busy += costs.setup;
    ++time.rays;
    step.next = now + costs.setup;
    step.what = "set-up";
    return step;
  }
  if (walk.next == log.events.size()) {
    step.done = true;
    return step;
  }
  const TraceEvent e = log.events[walk.next++];
  switch (e.kind) {
    case TraceEvent::Kind::kInner:
    case TraceEvent::Kind::kLeaf: {
      const bool leaf = e.kind == TraceEvent::Kind::kLeaf;
      const Cycle fetched = memory.read(now, e.address, spec::memory::kKdNodeBytes, true) + costs.memory_wait;
      const Cycle work = leaf ? costs.leaf : costs.inner;
      time.wait_memory += fetched - now;
      time.busy += work;
      ++(leaf ? time.leaves : time.inner);
      step.next = fetched + work;
      step.what = leaf ? "leaf" : "inner node";
      break;
    }
    case TraceEvent::Kind::kRef:
      step.next = memory.read(now, e.address, spec::memory::kPrimRefBytes, false) + costs.memory_wait;
      time.wait_memory += step.next - now;
      ++time.refs;
      step.what = "prim ref";
      break;
    case TraceEvent::Kind::kTest: {
      const Cycle fetched = memory.read(now, e.address, costs.record_bytes, false) + costs.memory_wait;
      time.wait_memory += fetched - now;
      // The IU that can take the test first; the slot waits for its answer.
      const auto iu = std::min_element(ius.begin(), ius.end(), [](const IuTimer& a, const IuTimer& b) {
        return a.next_accept < b.next_accept;
      });
      const Cycle accept = std::max(fetched, iu->next_accept);
      iu->next_accept = accept + costs.iu_interval;
      ++iu->time.tests;
      iu->time.busy += costs.iu_interval;
      step.next = accept + costs.iu_latency + costs.iu_wait;
      time.wait_iu += step.next - fetched;
      ++time.tests;
      step.what = "test";
      step.iu = static_cast<int>(iu - ius.begin());
      step.iu_accept = accept;
      break;
    }
    case TraceEvent::Kind::kPop:
      step.next = now + costs.pop;
      time.busy += costs.pop;
      ++time.pops;
      step.what = "pop";
      break;
  }
  return step;
}

}  // namespace rpu::cycle
