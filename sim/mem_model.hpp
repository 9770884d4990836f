#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "port_vectors.hpp"
#include "rpu/streams.hpp"

// The memory system as the Verilator harness drives it (sim/rpu_mem_cosim_top.sv)
// behind a plain interface, so the harness needs no Verilator header: one model per
// named configuration of spec/configs.toml and one of corner cases.
namespace rpu::sim {

// The top's shape (its localparams; verilated_mem.hpp checks the port widths).
inline constexpr std::size_t kMemCaches = 3;       // node, triangle, data: CacheId 0, 1, 2
inline constexpr std::size_t kRawPorts = 2;        // cache ports per cache
inline constexpr std::size_t kInOrderPorts = 1;    // traversal-unit ports per cache
inline constexpr std::size_t kRaw = kMemCaches * kRawPorts;
inline constexpr std::size_t kInOrder = kMemCaches * kInOrderPorts;
inline constexpr const char* kCacheNames[kMemCaches] = {"node", "triangle", "data"};

// A cache's build-time parameters, as the model reports them (geometry_o).
struct CacheGeometry {
  std::uint32_t bytes = 0, ways = 0, hit_latency = 0, mshrs = 0;
  std::uint32_t sets() const { return bytes / (streams::kDramLineBytes * ways); }
};

struct MemInputs {
  bool rst_n = false;
  std::array<bool, kRaw> req_valid{};
  std::array<streams::CacheReq, kRaw> req{};
  std::array<bool, kRaw> rsp_ready{};
  std::array<bool, kInOrder> mem_req_valid{};
  std::array<streams::MemReq, kInOrder> mem_req{};
  std::array<bool, kInOrder> mem_rsp_ready{};
  bool dram_req_ready = false;
  bool dram_rsp_valid = false;
  streams::DramRsp dram_rsp;
};

struct MemOutputs {
  std::array<bool, kRaw> req_ready{};
  std::array<bool, kRaw> rsp_valid{};
  std::array<streams::CacheRsp, kRaw> rsp{};
  std::array<bool, kInOrder> mem_req_ready{};
  std::array<bool, kInOrder> mem_rsp_valid{};
  std::array<streams::MemRsp, kInOrder> mem_rsp{};
  bool dram_req_valid = false;
  streams::DramReq dram_req;
  bool dram_rsp_ready = false;
  std::array<streams::CacheCounters, kMemCaches> counters{};
  std::array<bool, kMemCaches> idle{};
};

class MemModel {
 public:
  using Inputs = MemInputs;
  using Outputs = MemOutputs;
  virtual ~MemModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual MemOutputs settle(const MemInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  virtual std::array<CacheGeometry, kMemCaches> geometry() = 0;
  // The ports as they are after the last settle().
  virtual PortWords port_words() = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if
  // they could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

struct MemModelEntry {
  std::string name;  // a spec/configs.toml name, or "corners"
  std::string dram;  // the configuration whose DRAM serves it
};

// The models this build holds.
std::vector<MemModelEntry> mem_models();

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty;
// nullptr if no model of that name was built.
std::unique_ptr<MemModel> make_mem_model(const std::string& name, std::uint64_t seed, const std::string& fst);

}  // namespace rpu::sim
