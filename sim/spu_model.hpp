#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rpu/streams.hpp"

// One Verilated shader core (sim/rpu_spu_cosim_top.sv) behind a plain interface, so the
// harness needs no Verilator header: the models are built in their own library, one per
// named configuration of spec/configs.toml.
namespace rpu::sim {

struct SpuInputs {
  bool rst_n = false;
  bool code_we = false;
  std::uint32_t code_addr = 0;
  std::uint64_t code_data = 0;
  bool start = false;
  streams::Launch launch;
  bool stop = false;
  std::uint32_t stop_pixel = 0;
  bool cache_req_ready = false;
  bool cache_rsp_valid = false;
  streams::CacheRsp cache_rsp;
  bool trace_req_ready = false;
  bool trace_rsp_valid = false;
  streams::TraceRsp trace_rsp;
};

struct SpuOutputs {
  bool done = false;
  bool cache_req_valid = false;
  streams::CacheReq cache_req;
  bool cache_rsp_ready = false;
  bool trace_req_valid = false;
  streams::TraceReq trace_req;
  bool trace_rsp_ready = false;
  bool issue_valid = false;
  streams::Issue issue;
  bool retire_valid = false;
  streams::Retire retire;
  bool wb_valid = false;
  streams::Writeback wb;
  bool fault_valid = false;
  streams::Fault fault;
};

class SpuModel {
 public:
  using Inputs = SpuInputs;
  using Outputs = SpuOutputs;
  virtual ~SpuModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual SpuOutputs settle(const SpuInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // The code memory's words (rpu_spu CodeWords).
  virtual std::uint32_t code_words() const = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if
  // they could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

// The configurations a model was built for (spec/configs.toml names).
std::vector<std::string> spu_models();

// A fresh model of configuration `config` with every register and X initialised from
// `seed` (Verilator --x-assign unique --x-initial unique); waveforms to `fst` unless it
// is empty; nullptr if no model was built for it.
std::unique_ptr<SpuModel> make_spu_model(const std::string& config, std::uint64_t seed, const std::string& fst);

}  // namespace rpu::sim
