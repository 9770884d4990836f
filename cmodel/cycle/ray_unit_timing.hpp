// A traversal unit's timing as the chip drives it (docs/cycle-model.md "Traversal and
// intersection units"), whatever the unit: a walker (cycle/walker_timing.hpp) or a
// pipelined unit (cycle/tu_pipe_timing.hpp). The functional tracer has walked each ray
// already; a unit replays the walk's log and decides when each step happens.
#pragma once

#include <cstdint>
#include <optional>

#include "cycle/cycle_stats.hpp"
#include "cycle/dispatch.hpp"

namespace rpu::cycle {

// Where a unit's bytes come from: the node or triangle cache on the chip, a fixed-latency
// memory in tu_cosim. Returns the cycle the bytes are back when asked at `now`.
class LineSource {
 public:
  virtual ~LineSource() = default;
  virtual Cycle read(Cycle now, std::uint32_t address, std::uint32_t bytes, bool node) = 0;
};

// An intersection unit, shared by all traversal units: a test goes to the one that can
// take it first.
struct IuTimer {
  Cycle next_accept = 0;
  IntersectionUnitTime time;
};

class RayUnitTiming {
 public:
  // The unit's links to the chip: rays in from the dispatch, answers out to the cores.
  class Ports {
   public:
    virtual ~Ports() = default;
    // The next waiting ray (RayDispatch::next) for a walker free from `from`; the
    // ray's core has room in its queue again from then.
    virtual std::optional<Ray> next_ray(Cycle from) = 0;
    // The ray sent to pipelined unit `unit` in cycle `now` (RayDispatch::send).
    virtual std::optional<Ray> send_ray(Cycle now, std::size_t unit) = 0;
    virtual bool rays_waiting() const = 0;
    // The ray's answer leaves the unit in cycle `now`.
    virtual void answer(Ray& ray, Cycle now) = 0;
  };

  virtual ~RayUnitTiming() = default;
  // A ray waits at the dispatch from `at`: the unit takes one now if it is free, or
  // runs to take one. Returns the cycle it asks to run at (kNever: none).
  virtual Cycle ray_waiting(Cycle at) = 0;
  // Runs the unit in cycle `now`, one it asked for: it takes rays, steps them and
  // answers those done; returns the next cycle it asks for (kNever: none until a ray
  // waits).
  virtual Cycle advance(Cycle now) = 0;
  // A pipelined unit that would take a ray offered to it before it runs this cycle.
  virtual bool takes_ray() const { return false; }
  // Its times and counts in a launch of `end` cycles, in slot-cycles: busy, waiting for
  // memory, for the IU, and idle add up to `end` x its slots.
  virtual TraversalUnitTime time(Cycle end) const = 0;
};

}  // namespace rpu::cycle
