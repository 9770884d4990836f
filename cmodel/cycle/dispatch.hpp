// The rays between the shader cores and the traversal units (rtl/rpu_ray_dispatch.sv,
// docs/cycle-model.md "Traversal and intersection units").
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
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
  // another (rpu_ray_dispatch's Packets).
  explicit RayDispatch(std::size_t cores, bool packets = false) : queues_(cores), packets_(packets) {}

  // A ray reaches the dispatch at `at`.
  void queue(Ray ray, Cycle at);
  std::size_t waiting(std::uint32_t core) const { return queues_[core].size(); }
  bool any_waiting() const;
  // The next ray, whenever it arrives: a walker takes it as it frees and starts it when
  // it has arrived.
  std::optional<Ray> next();
  // The ray sent to pipelined unit `unit` in cycle `now`: the next of those arrived by
  // then, one a cycle to all units; a packet's rays to the unit that took its first.
  std::optional<Ray> send(Cycle now, std::size_t unit = 0);
  // A packet part sent to another unit keeps `unit` from taking rays.
  bool may_send_to(std::size_t unit) const { return !locked_ || unit == lock_unit_; }

 private:
  std::optional<Ray> take(Cycle arrived_by);

  std::vector<std::deque<Ray>> queues_;
  std::uint32_t last_core_ = 0;  // served last
  Cycle sent_at_ = kNever;       // send() sent a ray in this cycle
  bool packets_ = false;
  bool locked_ = false;          // a packet is being sent: the rest of it comes next
  std::uint32_t lock_core_ = 0;
  std::size_t lock_unit_ = 0;
};

}  // namespace rpu::cycle
