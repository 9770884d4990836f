// The rays between the shader cores and the traversal units (rtl/rpu_ray_dispatch.sv,
// docs/cycle-model.md "Traversal and intersection units").
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "cycle/event_queue.hpp"
#include "functional/tracer.hpp"

namespace rpu::cycle {

// A ray on its way from a shader core to a traversal unit and back: where its answer
// goes (the request's tag) and its walk as the functional tracer logged it.
struct Ray {
  std::uint32_t core = 0, chunk = 0, dst = 0;
  functional::TraceLog log;
  Cycle arrived = 0;        // the cycle it reached the dispatch
  Cycle taken = 0;          // the cycle a traversal unit took it
  bool packet_end = true;   // the last ray of its chunk's trace
};

// Each core's rays wait in its own queue, in order; the traversal units take them core
// by core in round robin after the core served last.
class RayDispatch {
 public:
  // With `packets`, a chunk's rays (up to one with packet_end) go to one unit one after
  // another (rpu_ray_dispatch's Packets): a core's packet holds its unit until its last
  // ray, while other cores send to other units.
  explicit RayDispatch(std::size_t cores, bool packets = false)
      : queues_(cores), packets_(packets), locked_(cores, false), lock_unit_(cores, 0) {}

  // A ray reaches the dispatch at `at`.
  void queue(Ray ray, Cycle at);
  std::size_t waiting(std::uint32_t core) const { return queues_[core].size(); }
  bool any_waiting() const;
  // The next ray, whenever it arrives: a walker takes it as it frees and starts it when
  // it has arrived.
  std::optional<Ray> next();
  // The ray sent in cycle `now` to a pipelined unit, and that unit, one a cycle: of the
  // units that take a ray in this cycle (`takes`), the next core in round robin whose
  // first ray has arrived sends it to the unit its packet holds, or else to the lowest
  // unit no other core's packet holds.
  struct Sent {
    std::size_t unit;
    Ray ray;
  };
  std::optional<Sent> send(Cycle now, const std::vector<bool>& takes);

 private:
  std::optional<Ray> take(Cycle arrived_by);
  // The unit core `core`'s next ray may go to, of those that take one.
  std::optional<std::size_t> unit_for(std::uint32_t core, const std::vector<bool>& takes) const;

  std::vector<std::deque<Ray>> queues_;
  std::uint32_t last_core_ = 0;  // served last
  bool packets_ = false;
  // Per core: a packet is being sent, the rest of it to lock_unit_.
  std::vector<bool> locked_;
  std::vector<std::size_t> lock_unit_;
};

}  // namespace rpu::cycle
