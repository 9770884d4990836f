#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "rpu/streams.hpp"

#include "rpu/spec.hpp"

// The cycle model's memory system (docs/cycle-model.md "Memory"): set-associative LRU
// caches with miss tracking in front of one DRAM channel. Each access is answered at
// once with the cycle its data arrives. The event loop makes most calls in time order,
// but not all (a step may book an access for a later cycle); the DRAM's banks and bus
// keep their bookings as intervals, so an access booked late for an earlier cycle uses
// the gaps the earlier bookings left.
namespace rpu::cycle {

using Cycle = std::uint64_t;

struct DramStats {
  std::uint64_t reads = 0, writes = 0;
  std::uint64_t bytes_read = 0, bytes_written = 0;
  std::uint64_t bus_cycles = 0;  // cycles the data bus carried data

  DramStats& operator+=(const DramStats& o) {
    reads += o.reads;
    writes += o.writes;
    bytes_read += o.bytes_read;
    bytes_written += o.bytes_written;
    bus_cycles += o.bus_cycles;
    return *this;
  }
};

// The busy intervals of one resource (a DRAM bank, the data bus), booked first come,
// first served in the order of the calls: a booking takes the first free stretch at or
// after the cycle asked for, so one asked for an earlier cycle than a booking made
// before it still finds the gap in front of that booking.
class Bookings {
 public:
  // The first cycle at or after `at` from which `length` cycles are free; they are booked.
  Cycle book(Cycle at, Cycle length);

 private:
  // Bookings that end this far before the latest cycle asked for are forgotten, and a
  // cycle asked for before that horizon is taken as the horizon, so the list stays short
  // and no forgotten booking is ever overlapped.
  static constexpr Cycle kHorizon = Cycle{1} << 16;
  struct Busy {
    Cycle begin, end;  // [begin, end)
  };
  std::vector<Busy> busy_;  // sorted, disjoint, touching ones merged
  std::size_t forgotten_ = 0;  // busy_[0, forgotten_) lie before the horizon
  Cycle latest_ = 0;
};

class Dram {
 public:
  // 64-byte blocks interleave over the banks.
  static constexpr std::uint32_t kInterleaveBytes = 64;

  explicit Dram(const spec::DramConfig& config);
  // A transfer of `bytes` at `address` requested at cycle `at`: the cycle it completes
  // (read data delivered, write data taken).
  Cycle access(Cycle at, std::uint32_t address, std::uint32_t bytes, bool write);
  // The chip's one memory port (rpu_mem_arbiter), which passes one request a cycle from
  // all caches: the cycle a request that would pass at `at` passes it.
  Cycle pass_port(Cycle at) { return port_.book(at, 1); }
  const DramStats& stats() const { return stats_; }
  const spec::DramConfig& config() const { return config_; }

 private:
  spec::DramConfig config_;
  std::vector<Bookings> banks_;
  Bookings bus_;
  Bookings port_;
  DramStats stats_;
};

struct CacheStats {
  std::uint64_t accesses = 0;  // lookups, one per piece a read moves (port_pieces)
  std::uint64_t hits = 0;
  std::uint64_t merged = 0;    // misses to a line already being filled (no new DRAM read)
  std::uint64_t misses = 0;    // DRAM reads
  std::uint64_t writes = 0;    // stores taken (no allocation; with write_back, one to a present line stays)
  std::uint64_t write_backs = 0;  // dirty lines written to DRAM (an eviction or the flush)
  std::uint64_t mshr_wait_cycles = 0;  // misses waiting for a free miss register

  double hit_rate() const { return accesses ? static_cast<double>(hits) / static_cast<double>(accesses) : 0.0; }
  CacheStats& operator+=(const CacheStats& o);
};

// The pieces a cache port moves for `bytes` at `address`, one a cycle (the RTL's
// cache_req: an aligned streams::kMemLineBytes each).
inline std::uint32_t port_pieces(std::uint32_t address, std::uint32_t bytes) {
  return (address + bytes - 1) / streams::kMemLineBytes - address / streams::kMemLineBytes + 1;
}

class Cache {
 public:
  // `line_wait`: the cycles a line read takes beyond the DRAM's (the chip's path to it).
  Cache(const spec::CacheConfig& config, Dram& dram, Cycle line_wait);
  // A read of `bytes` at `address` from cycle `at`: the port moves one piece
  // (streams::kMemLineBytes, aligned) a cycle, each a lookup, one a cycle for all its
  // requesters (rpu_cache_arbiter); the cycle all are there.
  Cycle read(Cycle at, std::uint32_t address, std::uint32_t bytes);
  // A store from cycle `at`, not allocated; a present line stays valid (the model keeps
  // no data, only tags). The port takes one piece a cycle: a piece of a present line in
  // a write-back cache marks the line dirty; any other is a request to memory that
  // waits for room in the cache's queue to the memory port. Returns the cycle the last
  // piece is taken.
  Cycle write(Cycle at, std::uint32_t address, std::uint32_t bytes);
  // Write-back: the end-of-frame flush from cycle `at`, the walk over every way of every
  // set (set by set, a way a cycle), each dirty line through the eviction buffer to
  // DRAM; the cycle the cache is idle (rpu_cache flush_i, idle_o).
  Cycle flush(Cycle at);
  const CacheStats& stats() const { return stats_; }

 private:
  struct Way {
    std::uint32_t line = 0;
    bool valid = false;
    Cycle last_use = 0;
    Cycle filled = 0;  // the cycle its fill arrives
    std::uint32_t replays = 0;  // reads merged into that fill, answered one a cycle after it
    bool dirty = false;
  };
  Cycle read_line(Cycle at, std::uint32_t line);
  // The ways of the set `line` maps to, config_.ways of them.
  Way* set_of(std::uint32_t line) {
    return &ways_[static_cast<std::size_t>(line % sets_) * static_cast<std::size_t>(config_.ways)];
  }
  // A request to memory that could enter the cache's queue at `at`: the cycle it enters
  // (a full queue holds it back) and the cycle it passes the memory port.
  struct Queued {
    Cycle entered, passed;
  };
  Queued queue_request(Cycle at);
  // A dirty line read into the eviction buffer at cycle `at` (its data-array read): the
  // buffer holds it from `at + 2` until the memory port passes it, ahead of the queue.
  void write_back(Cycle at, std::uint32_t line);

  spec::CacheConfig config_;
  Dram& dram_;
  Cycle line_wait_;
  std::uint32_t sets_;
  std::vector<Way> ways_;        // sets_ x config_.ways
  std::vector<Cycle> in_flight_;  // fill cycles of outstanding misses
  // The cycles the last streams::kCacheDramQueue requests passed the port, oldest first.
  std::deque<Cycle> queue_passed_;
  Bookings port_;  // the lookups, one a cycle
  Cycle buffer_free_ = 0;  // the first cycle the eviction buffer can take a line
  CacheStats stats_;
};

}  // namespace rpu::cycle
