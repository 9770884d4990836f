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

std::optional<Ray> RayDispatch::send(Cycle now, std::size_t unit) {
  if (sent_at_ == now || (locked_ && unit != lock_unit_)) return std::nullopt;
  std::optional<Ray> ray = take(now);
  if (ray) {
    sent_at_ = now;
    locked_ = packets_ && !ray->packet_end;
    lock_core_ = ray->core;
    lock_unit_ = unit;
  }
  return ray;
}

// The first ray of the next core, round robin, that has one arrived by `arrived_by`.
std::optional<Ray> RayDispatch::take(Cycle arrived_by) {
  const auto n = static_cast<std::uint32_t>(queues_.size());
  for (std::uint32_t k = 1; k <= n; ++k) {
    const std::uint32_t c = (last_core_ + k) % n;
    if (locked_ && c != lock_core_) continue;
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
