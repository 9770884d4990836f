#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "functional/tracer.hpp"
#include "rpu/streams.hpp"

// The agents a shader core's harness brings (docs/chip.md "Shader core"): the device's
// memory behind a cache port, the ray units behind the trace port, and the launch the
// host hands the core. Each answers after a random delay, in any order, so the core's
// tags are exercised; the random stream is the harness's (reproducible from its seed).
namespace rpu::sim {

// The device's address space as the RTL sees it: the image, the launch block, the
// firmware's data, the framebuffer and the thread stacks; bytes nobody wrote read as
// zero. Writes are allowed only to the framebuffer and the stacks (the core checks
// every other address itself), so any other write is an RTL failure.
class SparseMemory {
 public:
  SparseMemory(std::span<const std::uint8_t> image, std::span<const std::uint8_t> launch_block,
               std::span<const std::uint8_t> data, std::uint32_t pixels, std::uint32_t stack_bytes_total);
  std::uint32_t load32(std::uint32_t address) const;
  // Throws CosimFailure on a write outside the framebuffer and the stacks.
  void store32(std::uint32_t address, std::uint32_t value);
  std::vector<std::uint8_t> read(std::uint32_t address, std::uint32_t bytes) const;

 private:
  static constexpr std::uint32_t kPage = 4096;
  void put(std::uint32_t address, std::span<const std::uint8_t> bytes);
  std::unordered_map<std::uint32_t, std::vector<std::uint8_t>> pages_;
  std::uint32_t framebuffer_end_, stack_end_;
};

struct AgentTiming {
  int latency = 4;   // cycles at least
  int jitter = 12;   // plus up to this many more
};

// A cache port served from SparseMemory: reads answered by tag after their delay, in
// the order their delays end; writes applied when taken.
class CachePortServer {
 public:
  CachePortServer(SparseMemory& memory, AgentTiming timing, std::mt19937_64& rng)
      : memory_(memory), timing_(timing), rng_(rng) {}
  void take(const streams::CacheReq& req, std::uint64_t cycle);
  // The answer offered this cycle, if one is due.
  const streams::CacheRsp* offer(std::uint64_t cycle) const;
  void taken();  // the offered answer was taken
  bool idle() const { return pending_.empty(); }

 private:
  struct Pending {
    std::uint64_t due;
    streams::CacheRsp rsp;
  };
  SparseMemory& memory_;
  AgentTiming timing_;
  std::mt19937_64& rng_;
  std::vector<Pending> pending_;
  mutable std::size_t offered_ = 0;
};

// The ray units as the functional tracer: each ray answered after its delay, in the
// order the delays end, with the golden result (or a fault: the tracer's error). It
// checks the packets the core marks: the rays up to one with packet_end are one trace's
// (one pc), from its lanes in order.
class RayServer {
 public:
  RayServer(const functional::Tracer& tracer, AgentTiming timing, std::mt19937_64& rng)
      : tracer_(tracer), timing_(timing), rng_(rng) {}
  void take(const streams::TraceReq& req, std::uint64_t cycle);
  const streams::TraceRsp* offer(std::uint64_t cycle) const;
  void taken();
  bool idle() const { return pending_.empty(); }
  std::uint64_t rays() const { return rays_; }

 private:
  struct Pending {
    std::uint64_t due;
    streams::TraceRsp rsp;
  };
  const functional::Tracer& tracer_;
  AgentTiming timing_;
  std::mt19937_64& rng_;
  std::vector<Pending> pending_;
  mutable std::size_t offered_ = 0;
  std::uint64_t rays_ = 0;
  bool packet_open_ = false;  // rays came since the last packet_end
  std::uint32_t packet_pc_ = 0, packet_tag_ = 0;
};

}  // namespace rpu::sim
