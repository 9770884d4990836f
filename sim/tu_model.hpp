#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rpu/streams.hpp"

// One Verilated traversal unit (sim/rpu_tu_cosim_top.sv: the TU alone, its IU port
// open; or a top with the RTL IU inside) behind a plain interface, so the harness needs
// no Verilator header: the models are built in their own library.
namespace rpu::sim {

struct TuInputs {
  bool rst_n = false;
  streams::TuCfg cfg;
  bool req_valid = false;
  streams::TuReq req;
  bool rsp_ready = false;
  bool mem_req_ready = false;
  bool mem_rsp_valid = false;
  streams::MemRsp mem_rsp;
  bool iu_req_ready = false;  // the IU port exists only without the RTL IU
  bool iu_rsp_valid = false;
  streams::IuRsp iu_rsp;
};

struct TuOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  streams::TuRsp rsp;
  bool mem_req_valid = false;
  streams::MemReq mem_req;
  bool mem_rsp_ready = false;
  bool iu_req_valid = false;
  streams::IuReq iu_req;
  bool iu_rsp_ready = false;
};

class TuModel {
 public:
  using Inputs = TuInputs;
  using Outputs = TuOutputs;
  virtual ~TuModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual TuOutputs settle(const TuInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // Whether the IU port is open (the harness then answers it with the C++ IU).
  virtual bool has_iu_port() const = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if
  // they could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

struct TuModelName {
  std::string format, isect;
  bool with_iu;  // the RTL IU inside (rpu_ray_unit), else the IU port is open
  int slots = 1;  // ray slots of the TU (rpu_tu_slots)
  bool pipe = false;  // the slots share a node-step pipeline (rpu_tu_pipe)
  int setups = 0;     // ... and its set-up engines (not part of the lookup: one build per pipe)
};

// The models built into this binary.
std::vector<TuModelName> tu_models();

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty;
// nullptr if the model was not built.
std::unique_ptr<TuModel> make_tu_model(const TuModelName& name, std::uint64_t seed, const std::string& fst);

}  // namespace rpu::sim
