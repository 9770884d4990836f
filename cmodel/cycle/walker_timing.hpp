// The timing of a walker's walk (docs/cycle-model.md, "Traversal and intersection
// units"): each event of the tracer's log (a node fetched and stepped, a prim ref read,
// a record read and tested, a pop) costs the configuration's step cycles plus the wait
// for its memory line and IU answer. The chip's cycle model and tu_cosim's comparison
// with the RTL ray unit (--cycle-model) time walks with this one code.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "cycle/ray_unit_timing.hpp"
#include "cycle/timeline.hpp"
#include "functional/tracer.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

namespace rpu::cycle {

// A configuration's step cycles for one intersection mode (spec/latencies.toml [tu], [iu]);
// of() is where they come from.
struct WalkCosts {
  Cycle setup, inner, leaf, pop;
  Cycle memory_wait, iu_wait, turnaround;
  Cycle iu_latency, iu_interval;
  std::uint32_t record_bytes;

  static WalkCosts of(const spec::HardwareConfig& config, IsectMode mode);
};

// Where a slot is in its ray's log.
struct Walk {
  std::size_t next = 0;  // the next event of the log
  bool set_up = false;
};

// What one step did: when the slot's next step can start (done: the walk has ended at
// `now` and its answer leaves), and for the timeline its name and the IU test it made.
struct WalkStep {
  bool done = false;
  Cycle next = 0;
  std::string_view what;
  int iu = -1;  // the IU that took a test, and when
  Cycle iu_accept = 0;
};

// Times the slot's next step at `now`; `time` collects the slot's cycles and counts.
// A test goes to the IU that can take it first.
WalkStep step_walk(const functional::TraceLog& log, Walk& walk, Cycle now, const WalkCosts& costs,
                   LineSource& memory, std::span<IuTimer> ius, TraversalUnitTime& time);

// A walker of the chip (one slot of rpu_tu_slots): one ray at a time, stepped by
// step_walk. It takes the next waiting ray as it frees, `turnaround` cycles after its
// last answer left, and starts it when the ray has arrived.
class WalkerTiming final : public RayUnitTiming {
 public:
  // Its steps on the timeline's `track`.
  WalkerTiming(const WalkCosts& costs, LineSource& lines, std::span<IuTimer> ius, Ports& ports, Timeline& timeline,
               std::string track);

  Cycle ray_waiting(Cycle at) override { return ray_ ? kNever : take(at); }
  Cycle advance(Cycle now) override;
  TraversalUnitTime time(Cycle end) const override;

 private:
  // Takes the next waiting ray, free from `from`; the cycle it starts (kNever: none).
  Cycle take(Cycle from);

  WalkCosts costs_;
  LineSource& lines_;
  std::span<IuTimer> ius_;
  Ports& ports_;
  Timeline& timeline_;
  std::string track_;
  std::optional<Ray> ray_;
  Walk walk_;
  TraversalUnitTime time_;
};

}  // namespace rpu::cycle
