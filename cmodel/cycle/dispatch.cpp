#include "cycle/dispatch.hpp"

#include <algorithm>

namespace rpu::cycle {

void RayDispatch::queue(Ray ray, Cycle at) {
  ray.arrived = at;
  queues_[ray.core].push_back(std::move(ray));
}

bool RayDispatch::any_waiting() const {
  return std::any_of(queues_.begin(), queues_.end(), [](const std::deque<Ray>& q) { return !q.empty(); });
}

std::optional<Ray> RayDispatch::next() { return take(kNever); }

std::optional<std::size_t> RayDispatch::unit_for(std::uint32_t core, const std::vector<bool>& takes) const {
  if (locked_[core]) return takes[lock_unit_[core]] ? std::optional(lock_unit_[core]) : std::nullopt;
  for (std::size_t u = 0; u < takes.size(); ++u) {
    if (!takes[u]) continue;
    bool held = false;
    for (std::size_t c = 0; c < queues_.size(); ++c) held = held || (locked_[c] && lock_unit_[c] == u);
    if (!held) return u;
  }
  return std::nullopt;
}

std::optional<RayDispatch::Sent> RayDispatch::send(Cycle now, const std::vector<bool>& takes) {
  const auto n = static_cast<std::uint32_t>(queues_.size());
  for (std::uint32_t k = 1; k <= n; ++k) {
    const std::uint32_t c = (last_core_ + k) % n;
    std::deque<Ray>& q = queues_[c];
    if (q.empty() || q.front().arrived > now) continue;
    const std::optional<std::size_t> unit = unit_for(c, takes);
    if (!unit) continue;
    last_core_ = c;
    Sent sent{*unit, std::move(q.front())};
    q.pop_front();
    locked_[c] = packets_ && !sent.ray.packet_end;
    lock_unit_[c] = *unit;
    return sent;
  }
  return std::nullopt;
}

// The first ray of the next core, round robin, that has one arrived by `arrived_by`.
std::optional<Ray> RayDispatch::take(Cycle arrived_by) {
  const auto n = static_cast<std::uint32_t>(queues_.size());
  for (std::uint32_t k = 1; k <= n; ++k) {
    const std::uint32_t c = (last_core_ + k) % n;
    std::deque<Ray>& q = queues_[c];
    if (q.empty() || q.front().arrived > arrived_by) continue;
    last_core_ = c;
    Ray ray = std::move(q.front());
    q.pop_front();
    return ray;
  }
  return std::nullopt;
}

}  // namespace rpu::cycle
