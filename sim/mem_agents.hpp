#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <list>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "cosim_core.hpp"
#include "cycle/memory_system.hpp"
#include "mem_shape.hpp"
#include "rpu/spec.hpp"
#include "rpu/streams.hpp"

// The agents of the memory system's co-simulation (docs/memory-system.md): requesters
// that read and write a few lines that conflict in a few sets, the memory behind the
// chip's memory port timed by the cycle model's DRAM, and the references the answers
// are checked against.
namespace rpu::sim {

// Words of a sparse memory; a word nobody wrote holds initial_word(address), so that
// reads of untouched memory are checked too.
class WordMemory {
 public:
  static std::uint32_t initial_word(std::uint32_t address);
  std::uint32_t load(std::uint32_t address) const;
  void store(std::uint32_t address, std::uint32_t value);
  // Every address written, for comparing two memories.
  std::vector<std::uint32_t> written() const;

 private:
  std::unordered_map<std::uint32_t, std::uint32_t> words_;
};

// Which cache an address belongs to: each cache's traffic lives in its own 16 MiB, so
// that the caches (which are not coherent with each other) never share a line.
inline constexpr std::uint32_t kCacheSpanBits = 24;
inline std::size_t cache_of(std::uint32_t address) { return address >> kCacheSpanBits; }

// Addresses of MemLineBytes pieces that make one cache's lines conflict: most fall in
// a few hot sets, each with Ways + 2 lines (so the set evicts), the rest anywhere in
// 8 x the cache's lines.
class AddressPicker {
 public:
  AddressPicker(std::size_t cache, const streams::CacheGeometry& geometry, std::mt19937_64& rng);
  std::uint32_t pick(std::mt19937_64& rng) const;
  // The distinct lines of the hot sets: at most so many misses of them at once.
  std::uint64_t hot_lines() const { return hot_sets_.size() * (geometry_.ways + 2); }

 private:
  std::uint32_t base_;
  streams::CacheGeometry geometry_;
  std::vector<std::uint32_t> hot_sets_;
};

// A read taken at a port: what it must return (the reference memory when the cache
// took it) and when it was taken.
struct ExpectedRead {
  std::uint32_t addr = 0;
  std::array<std::uint32_t, streams::kMemLineBytes / 4> data{};
  std::uint64_t taken = 0;
  std::uint32_t tag = 0;  // an in-order port's: the unit's own, returned with the answer
  bool hit = false;  // the LRU reference's prediction (one request at a time only)
};

// The chip's memory port answered by the cycle model's DRAM (cycle::Dram, the same code
// the cycle backend times with): a line read is answered from the cycle Dram::access
// gives for it, with the memory's words at the cycle the port took it; a write is
// applied when taken and occupies the DRAM's bank and bus as its bytes do. Answers go
// out earliest first, each held until taken.
class DramServer {
 public:
  explicit DramServer(const spec::DramConfig& config);
  void take(const streams::DramReq& req, std::uint64_t cycle);
  // The answer offered this cycle: the one already offered, else the earliest due if
  // `may_offer`.
  const streams::DramRsp* offer(std::uint64_t cycle, bool may_offer);
  void taken();
  bool idle() const { return reads_.empty(); }
  // A line read of this line is in flight.
  bool reading(std::uint32_t line_address) const;
  const WordMemory& memory() const { return memory_; }

  struct CacheCounts {
    std::uint64_t reads = 0, writes = 0, refetches = 0;  // refetch: a line read before
    std::uint64_t line_writes = 0;  // writes of a whole line (a write-back cache's evictions)
  };
  const std::array<CacheCounts, kMemCaches>& counts() const { return counts_; }
  const cycle::Dram& dram() const { return dram_; }

 private:
  struct Read {
    std::uint64_t due = 0, serial = 0;
    streams::DramRsp rsp;
    std::uint32_t addr = 0;
  };
  cycle::Dram dram_;
  WordMemory memory_;
  PendingByTag<Read> reads_;
  std::vector<std::uint32_t> in_flight_tags_;
  bool offering_ = false;
  std::uint32_t offered_tag_ = 0;
  std::uint64_t serial_ = 0;
  std::array<CacheCounts, kMemCaches> counts_{};
  std::unordered_map<std::uint32_t, bool> fetched_;  // lines read before
};

// The tag array of a cache as a list per set, the most recently read line first: what
// an LRU cache that installs every miss holds, when no two misses overlap.
class LruReference {
 public:
  explicit LruReference(const streams::CacheGeometry& geometry) : geometry_(geometry), sets_(cache_sets(geometry)) {}
  // A read of the line: whether it hits; the line becomes the newest of its set.
  bool read(std::uint32_t line);

 private:
  streams::CacheGeometry geometry_;
  std::vector<std::list<std::uint32_t>> sets_;
};

}  // namespace rpu::sim
