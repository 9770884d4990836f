#include "cycle/event_queue.hpp"

namespace rpu::cycle {

void EventQueue::wake(std::uint32_t agent, Cycle at) {
  if (at >= pending_[agent]) return;
  pending_[agent] = at;
  entries_.push({at, made_++, agent});
}

std::optional<EventQueue::Wakeup> EventQueue::next() {
  while (!entries_.empty()) {
    const Entry e = entries_.top();
    entries_.pop();
    now_ = e.at;
    // An entry whose agent was since woken earlier (or has run) is not its wake-up.
    if (pending_[e.agent] != e.at) continue;
    pending_[e.agent] = kNever;
    return Wakeup{e.at, e.agent};
  }
  return std::nullopt;
}

}  // namespace rpu::cycle
