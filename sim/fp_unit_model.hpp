#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rpu/streams.hpp"

// One Verilated floating-point unit (rpu_fp_cosim_top.sv) behind a plain interface,
// so the harness needs no Verilator header: the models are built in their own
// library, compiled with Verilator's flags rather than the project's warnings.
namespace rpu::sim {

struct FpUnitInputs {
  bool rst_n = false;
  bool req_valid = false;
  streams::FpReq req;
  bool rsp_ready = false;
};

struct FpUnitOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  streams::FpRsp rsp;
};

class FpUnitModel {
 public:
  using Inputs = FpUnitInputs;
  using Outputs = FpUnitOutputs;
  virtual ~FpUnitModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual FpUnitOutputs settle(const FpUnitInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if
  // they could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

struct FpUnitModelName {
  std::string unit, format;
};

// The (unit, format) pairs built into this binary.
std::vector<FpUnitModelName> fp_unit_models();

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty;
// nullptr if the pair was not built.
std::unique_ptr<FpUnitModel> make_fp_unit_model(std::string_view unit, std::string_view format,
                                                std::uint64_t seed, const std::string& fst = "");

}  // namespace rpu::sim
