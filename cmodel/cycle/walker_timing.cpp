#include "cycle/walker_timing.hpp"

#include <algorithm>

#include <fmt/format.h>

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

WalkerTiming::WalkerTiming(const WalkCosts& costs, LineSource& lines, std::span<IuTimer> ius, Ports& ports,
                           Timeline& timeline, std::string track)
    : costs_(costs), lines_(lines), ius_(ius), ports_(ports), timeline_(timeline), track_(std::move(track)) {}

Cycle WalkerTiming::take(Cycle from) {
  std::optional<Ray> ray = ports_.next_ray(from);
  if (!ray) return kNever;
  ray_ = std::move(ray);
  walk_ = {};
  ray_->taken = std::max(from, ray_->arrived);
  return ray_->taken;
}

Cycle WalkerTiming::advance(Cycle now) {
  const WalkStep step = step_walk(ray_->log, walk_, now, costs_, lines_, ius_, time_);
  if (step.done) {
    ports_.answer(*ray_, now);
    ray_.reset();
    return take(now + costs_.turnaround);
  }
  if (timeline_.enabled()) {
    timeline_.add(track_, std::string(step.what), now, step.next);
    if (step.iu >= 0) timeline_.add(fmt::format("IU {}", step.iu), "test", step.iu_accept, step.iu_accept + costs_.iu_latency);
  }
  return step.next;
}

TraversalUnitTime WalkerTiming::time(Cycle end) const {
  TraversalUnitTime t = time_;
  t.idle = end - std::min(end, t.busy + t.wait_memory + t.wait_iu);
  return t;
}

}  // namespace rpu::cycle
