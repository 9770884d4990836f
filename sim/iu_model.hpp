#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rpu/streams.hpp"
#include "stream_unit_model.hpp"

// The Verilated intersection units (rpu_iu_cosim_top.sv), one per format and mode,
// behind StreamUnitModel.
namespace rpu::sim {

using IuModel = StreamUnitModel<streams::IuReq, streams::IuRsp>;
using IuInputs = IuModel::Inputs;
using IuOutputs = IuModel::Outputs;

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
