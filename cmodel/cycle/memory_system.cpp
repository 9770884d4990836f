#include "cycle/memory_system.hpp"

#include <algorithm>
#include <iterator>

namespace rpu::cycle {

Cycle Bookings::book(Cycle at, Cycle length) {
  latest_ = std::max(latest_, at);
  const Cycle horizon = latest_ > kHorizon ? latest_ - kHorizon : 0;
  while (forgotten_ < busy_.size() && busy_[forgotten_].end <= horizon) ++forgotten_;
  if (forgotten_ > busy_.size() / 2) {
    busy_.erase(busy_.begin(), busy_.begin() + static_cast<std::ptrdiff_t>(forgotten_));
    forgotten_ = 0;
  }
  Cycle start = std::max(at, horizon);
  if (length == 0) return start;
  // The first booking that ends after `start`; walk the gaps from there.
  auto it = std::upper_bound(busy_.begin() + static_cast<std::ptrdiff_t>(forgotten_), busy_.end(), start,
                             [](Cycle c, const Busy& b) { return c < b.end; });
  while (it != busy_.end() && it->begin < start + length) {
    start = std::max(start, it->end);
    ++it;
  }
  // [start, start + length) lies between it[-1] and *it; merge with the ones it touches.
  const bool joins_before = it != busy_.begin() + static_cast<std::ptrdiff_t>(forgotten_) && std::prev(it)->end == start;
  const bool joins_after = it != busy_.end() && it->begin == start + length;
  if (joins_before && joins_after) {
    std::prev(it)->end = it->end;
    busy_.erase(it);
  } else if (joins_before) {
    std::prev(it)->end = start + length;
  } else if (joins_after) {
    it->begin = start;
  } else {
    busy_.insert(it, {start, start + length});
  }
  return start;
}

Dram::Dram(const spec::DramConfig& config) : config_(config), banks_(static_cast<std::size_t>(config.banks)) {}

Cycle Dram::access(Cycle at, std::uint32_t address, std::uint32_t bytes, bool write) {
  Bookings& bank = banks_[(address / kInterleaveBytes) % banks_.size()];
  const Cycle start = bank.book(at, static_cast<Cycle>(config_.bank_busy));
  const auto per_cycle = static_cast<std::uint32_t>(config_.bytes_per_cycle);
  const Cycle transfer = (bytes + per_cycle - 1) / per_cycle;
  const Cycle done = bus_.book(start + static_cast<Cycle>(config_.latency), transfer) + transfer;
  stats_.bus_cycles += transfer;
  if (write) {
    ++stats_.writes;
    stats_.bytes_written += bytes;
  } else {
    ++stats_.reads;
    stats_.bytes_read += bytes;
  }
  return done;
}

CacheStats& CacheStats::operator+=(const CacheStats& o) {
  accesses += o.accesses;
  hits += o.hits;
  merged += o.merged;
  misses += o.misses;
  writes += o.writes;
  write_backs += o.write_backs;
  mshr_wait_cycles += o.mshr_wait_cycles;
  return *this;
}

Cache::Cache(const spec::CacheConfig& config, Dram& dram, Cycle line_wait)
    : config_(config),
      dram_(dram),
      line_wait_(line_wait),
      sets_(static_cast<std::uint32_t>(config.bytes / (config.line_bytes * config.ways))),
      ways_(static_cast<std::size_t>(sets_) * static_cast<std::size_t>(config.ways)) {}

Cycle Cache::read(Cycle at, std::uint32_t address, std::uint32_t bytes) {
  const auto line_bytes = static_cast<std::uint32_t>(config_.line_bytes);
  const std::uint32_t first = address / streams::kMemLineBytes;
  Cycle done = 0;
  for (std::uint32_t k = 0; k < port_pieces(address, bytes); ++k) {
    done = std::max(done, read_line(port_.book(at + k, 1), (first + k) * streams::kMemLineBytes / line_bytes));
  }
  return done;
}

Cycle Cache::read_line(Cycle at, std::uint32_t line) {
  ++stats_.accesses;
  const auto ways = static_cast<std::size_t>(config_.ways);
  Way* set = set_of(line);
  const Cycle looked_up = at + static_cast<Cycle>(config_.hit_latency);
  Way* victim = set;
  for (std::size_t w = 0; w < ways; ++w) {
    Way& way = set[w];
    if (way.valid && way.line == line) {
      way.last_use = at;
      if (way.filled <= at) {
        ++stats_.hits;
        return looked_up;
      }
      // The reads waiting for a fill are answered one a cycle after the line's own.
      ++stats_.merged;
      return std::max(looked_up, way.filled + ++way.replays);
    }
    // The least recently used way, invalid ones first, the lowest index on a tie.
    if (!way.valid ? victim->valid : (victim->valid && way.last_use < victim->last_use)) victim = &way;
  }
  ++stats_.misses;
  std::erase_if(in_flight_, [&](Cycle c) { return c <= looked_up; });
  Cycle request = looked_up;
  if (in_flight_.size() >= static_cast<std::size_t>(config_.mshrs)) {
    const auto earliest = std::min_element(in_flight_.begin(), in_flight_.end());
    // A miss register is free again the cycle after its fill is installed.
    request = *earliest + 1;
    stats_.mshr_wait_cycles += request - looked_up;
    in_flight_.erase(earliest);
  }
  const auto line_bytes = static_cast<std::uint32_t>(config_.line_bytes);
  const Cycle filled = dram_.access(queue_request(request).passed, line * line_bytes, line_bytes, false) + line_wait_;
  in_flight_.push_back(filled);
  // The fill's install reads a dirty victim out (the model picks the victim at the miss).
  if (victim->valid && victim->dirty) write_back(filled - line_wait_ + 1, victim->line);
  *victim = {line, true, at, filled, 0, false};
  return filled;
}

void Cache::write_back(Cycle at, std::uint32_t line) {
  const Cycle read = std::max(at, buffer_free_);
  const Cycle passed = dram_.pass_port(read + 2);
  buffer_free_ = passed + 1;
  const auto line_bytes = static_cast<std::uint32_t>(config_.line_bytes);
  dram_.access(passed, line * line_bytes, line_bytes, true);
  ++stats_.write_backs;
}

Cycle Cache::flush(Cycle at) {
  // Idle once no line is dirty and the eviction buffer is empty: the walk past the last
  // dirty line does not count.
  Cycle t = at, idle = at;
  for (Way& way : ways_) {  // set by set, a way a cycle (ways_ is set-major)
    if (way.valid && way.dirty) {
      t = std::max(t, buffer_free_);
      write_back(t, way.line);
      way.dirty = false;
      idle = buffer_free_;
    }
    ++t;
  }
  return idle;
}

Cycle Cache::write(Cycle at, std::uint32_t address, std::uint32_t bytes) {
  const std::uint32_t end = address + bytes;
  Cycle next = at, taken = at;
  for (std::uint32_t piece = address / streams::kMemLineBytes * streams::kMemLineBytes; piece < end;
       piece += streams::kMemLineBytes) {
    ++stats_.writes;
    if (config_.write_back) {
      const std::uint32_t line = piece / static_cast<std::uint32_t>(config_.line_bytes);
      Way* set = set_of(line);
      Way* end_of_set = set + config_.ways;
      Way* present = std::find_if(set, end_of_set, [&](const Way& w) { return w.valid && w.line == line; });
      if (present != end_of_set) {
        present->dirty = true;
        taken = next;
        ++next;
        continue;
      }
    }
    const std::uint32_t from = std::max(address, piece);
    const std::uint32_t to = std::min(end, piece + streams::kMemLineBytes);
    const Queued q = queue_request(next);
    taken = q.entered;
    next = taken + 1;
    dram_.access(q.passed, from, to - from, true);
  }
  return taken;
}

// The queue's entries leave in order, one a cycle at most, as the port passes them; an
// entry's place is free two cycles after the one in it passed (the RTL's FIFO counts
// the pop in the cycle after it, and the pass is a cycle after the request's in the
// RTL, which line_wait holds for reads).
Cache::Queued Cache::queue_request(Cycle at) {
  Cycle entered = at;
  if (queue_passed_.size() == streams::kCacheDramQueue) {
    entered = std::max(entered, queue_passed_.front() + 2);
    queue_passed_.pop_front();
  }
  const Cycle passed = dram_.pass_port(queue_passed_.empty() ? entered : std::max(entered, queue_passed_.back() + 1));
  queue_passed_.push_back(passed);
  return {entered, passed};
}

}  // namespace rpu::cycle
