#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "port_vectors.hpp"
#include "rpu/streams.hpp"

// One Verilated chip (rtl/rpu_top.sv through sim/rpu_chip_cosim_top.sv) behind a plain
// interface, so the harness and the rtl backend need no Verilator header: the models are
// built in their own library, one per named configuration of spec/configs.toml and
// intersection test.
namespace rpu::sim {

inline constexpr int kMaxCores = 1 << streams::kCoreBits;

struct ChipInputs {
  bool rst_n = false;
  bool code_we = false;
  std::uint32_t code_addr = 0;
  std::uint64_t code_data = 0;
  bool start = false;
  streams::Launch launch;
  streams::TuCfg tu_cfg;
  bool dram_req_ready = false;
  bool dram_rsp_valid = false;
  streams::DramRsp dram_rsp;
};

// One core's trace-port records of a cycle; a record is filled only when valid.
struct CoreRecords {
  bool issue_valid = false, retire_valid = false, wb_valid = false, fault_valid = false;
  streams::Issue issue;
  streams::Retire retire;
  streams::Writeback wb;
  streams::Fault fault;
};

struct ChipOutputs {
  bool done = false;
  bool dram_req_valid = false;
  streams::DramReq dram_req;
  bool dram_rsp_ready = false;
  std::array<CoreRecords, kMaxCores> cores;  // the first cores() are the chip's
};

// The chip's counters (rpu_top's counters ports), read at the end of a frame.
struct ChipCounters {
  std::vector<streams::CoreCounters> cores;
  std::vector<streams::RayUnitCounters> ray_units;
  std::vector<streams::CacheCounters> caches;  // node, triangle, then core c's data cache
};

class ChipModel {
 public:
  using Inputs = ChipInputs;
  using Outputs = ChipOutputs;
  virtual ~ChipModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual ChipOutputs settle(const ChipInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  virtual int cores() const = 0;
  virtual int ray_units() const = 0;
  // The counters as the last settle or clock left them.
  virtual ChipCounters counters() = 0;
  virtual std::uint32_t code_words() const = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if
  // they could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
  // Waveforms of the cycles [begin, end) only (counted from the model's first cycle).
  virtual void set_wave_window(std::uint64_t begin, std::uint64_t end) = 0;
  // The ports as they are after the last settle(), in rpu_chip_cosim_top's port order
  // (what chip_cosim --write-vectors records for sim/rpu_chip_netlist_tb.sv).
  virtual PortWords port_words() = 0;
};

struct ChipModelName {
  std::string config, isect;
};

// The (configuration, intersection test) pairs built into this binary.
std::vector<ChipModelName> chip_models();

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty;
// nullptr if the pair was not built.
std::unique_ptr<ChipModel> make_chip_model(const ChipModelName& name, std::uint64_t seed, const std::string& fst);

}  // namespace rpu::sim
