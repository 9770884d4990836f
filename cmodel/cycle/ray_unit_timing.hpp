// The timing of a ray slot's walk (docs/cycle-model.md, "Traversal and intersection
// units"): each event of the tracer's log (a node fetched and stepped, a prim ref read,
// a record read and tested, a pop) costs the configuration's step cycles plus the wait
// for its memory line and IU answer. The chip's cycle model and tu_cosim's comparison
// with the RTL ray unit (--cycle-model) time walks with this one code.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "rpu/spec.hpp"
#include "cycle/cycle_stats.hpp"
#include "functional/tracer.hpp"
#include "memory/memory_image.hpp"

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

// Where a walk's bytes come from: the node or triangle cache on the chip, a fixed-latency
// memory in tu_cosim. Returns the cycle the bytes are back when asked at `now`.
class LineSource {
 public:
  virtual ~LineSource() = default;
  virtual Cycle read(Cycle now, std::uint32_t address, std::uint32_t bytes, bool node) = 0;
};

struct IuTimer {
  Cycle next_accept = 0;
  IntersectionUnitTime time;
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

}  // namespace rpu::cycle
