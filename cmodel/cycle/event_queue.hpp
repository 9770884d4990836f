// The cycle model's clock (docs/cycle-model.md "Events and host cost"): the units it
// times are agents woken at the cycle their next step can happen, so cycles in which
// nothing happens cost no host time.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <vector>

#include "cycle/memory_system.hpp"

namespace rpu::cycle {

inline constexpr Cycle kNever = std::numeric_limits<Cycle>::max();

// Wake-ups of agents 0 .. agents-1 in cycle order; those of one cycle in the order they
// were made, so that the same inputs give the same cycles. An agent has at most one
// wake-up pending: waking it earlier replaces the pending one, waking it later (or at
// kNever) changes nothing.
class EventQueue {
 public:
  struct Wakeup {
    Cycle at;
    std::uint32_t agent;
  };

  explicit EventQueue(std::size_t agents) : pending_(agents, kNever) {}

  void wake(std::uint32_t agent, Cycle at);
  // The next wake-up, no longer pending once returned; none when no agent has one.
  std::optional<Wakeup> next();
  // The cycle of the last wake-up taken from the queue, a replaced one too: the frame
  // ends after the last wake-up made.
  Cycle now() const { return now_; }

 private:
  struct Entry {
    Cycle at;
    std::uint64_t order;  // when it was made
    std::uint32_t agent;
    bool operator>(const Entry& o) const { return at != o.at ? at > o.at : order > o.order; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> entries_;
  std::vector<Cycle> pending_;  // per agent
  std::uint64_t made_ = 0;
  Cycle now_ = 0;
};

}  // namespace rpu::cycle
