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
  Cycle arrived = 0;  // the cycle it reached the dispatch
};

// Each core's rays wait in its own queue, in order; the traversal units take them core
// by core in round robin after the core served last.
class RayDispatch {
 public:
  explicit RayDispatch(std::size_t cores) : queues_(cores) {}

  // A ray reaches the dispatch at `at`.
  void queue(Ray ray, Cycle at);
  std::size_t waiting(std::uint32_t core) const { return queues_[core].size(); }
  bool any_waiting() const;
  // The next ray, whenever it arrives: a walker takes it as it frees and starts it when
  // it has arrived.
  std::optional<Ray> next();
  // The ray sent to a pipelined unit in cycle `now`: the next of those arrived by then,
  // one a cycle to all units.
  std::optional<Ray> send(Cycle now);

 private:
  std::optional<Ray> take(Cycle arrived_by);

  std::vector<std::deque<Ray>> queues_;
  std::uint32_t last_core_ = 0;  // served last
  Cycle sent_at_ = kNever;       // send() sent a ray in this cycle
};

}  // namespace rpu::cycle
