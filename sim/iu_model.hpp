#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rpu/streams.hpp"

// One Verilated intersection unit (rpu_iu_cosim_top.sv) behind a plain interface, so
// the harness needs no Verilator header (as fp_unit_model.hpp does for the FP units).
namespace rpu::sim {

struct IuInputs {
  bool rst_n = false;
  bool req_valid = false;
  streams::IuReq req;
  bool rsp_ready = false;
};

struct IuOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  streams::IuRsp rsp;
};

class IuModel {
 public:
  using Inputs = IuInputs;
  using Outputs = IuOutputs;
  virtual ~IuModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual IuOutputs settle(const IuInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // Closes the waveforms and renames them over the path; rpu::Error naming it if they
  // could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

struct IuModelName {
  std::string format, isect;
};

// The (format, intersection mode) pairs built into this binary.
std::vector<IuModelName> iu_models();

// A fresh model with registers and X initialised from `seed`; FST waveforms of every
// evaluation to `fst` unless it is empty; nullptr if not built.
std::unique_ptr<IuModel> make_iu_model(std::string_view format, std::string_view isect, std::uint64_t seed,
                                       const std::string& fst);

}  // namespace rpu::sim
