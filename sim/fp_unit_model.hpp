#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rpu/streams.hpp"
#include "stream_unit_model.hpp"

// The Verilated floating-point units (rpu_fp_cosim_top.sv), one per unit and format,
// behind StreamUnitModel.
namespace rpu::sim {

using FpUnitModel = StreamUnitModel<streams::FpReq, streams::FpRsp>;
using FpUnitInputs = FpUnitModel::Inputs;
using FpUnitOutputs = FpUnitModel::Outputs;

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
