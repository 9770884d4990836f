#pragma once

#include <cstdint>
#include <vector>

#include "cycle/memory_system.hpp"
#include "rpu/streams.hpp"
#include "spu_agents.hpp"

// The chip's memory port served as the cycle model's DRAM serves its caches
// (cycle::Dram, the same code): a request taken at cycle `now` is done at the cycle
// Dram::access returns; a read's line is answered then, by tag, in the order reads
// finish. The data live in SparseMemory: a write is applied when it is taken and a read
// sees every write taken before it, which is the order the chip's one port gives.
namespace rpu::sim {

class DeviceDram {
 public:
  DeviceDram(SparseMemory& memory, const spec::DramConfig& config) : memory_(memory), dram_(config) {}
  void take(const streams::DramReq& req, std::uint64_t now);
  const streams::DramRsp* offer(std::uint64_t now) const;
  void taken();
  bool idle() const { return pending_.empty(); }
  const cycle::DramStats& stats() const { return dram_.stats(); }

 private:
  struct Pending {
    std::uint64_t due, order;
    streams::DramRsp rsp;
  };
  SparseMemory& memory_;
  cycle::Dram dram_;
  std::vector<Pending> pending_;
  std::uint64_t order_ = 0;
  mutable std::size_t offered_ = 0;
};

}  // namespace rpu::sim
