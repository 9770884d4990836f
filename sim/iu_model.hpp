#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

// One Verilated intersection unit (rpu_iu_cosim_top.sv) behind a plain interface, so
// the harness needs no Verilator header (as fp_unit_model.hpp does for the FP units).
namespace rpu::sim {

struct IuInputs {
  bool rst_n = false;
  bool req_valid = false;
  std::uint32_t tag = 0;
  std::array<std::uint32_t, 3> origin{}, direction{};
  std::uint32_t t_min = 0, t_best = 0;
  std::uint32_t kx = 0, ky = 1, kz = 2;
  std::array<std::uint32_t, 2> shear{};
  std::array<std::uint32_t, 12> record{};
  bool rsp_ready = false;
};

struct IuOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  std::uint32_t tag = 0;
  bool hit = false;
  std::uint32_t t = 0, u = 0, v = 0;
};

class IuModel {
 public:
  virtual ~IuModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual IuOutputs settle(const IuInputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // From now on, FST waveforms of every evaluation for `path` (FstOutput).
  virtual void trace(const std::string& path) = 0;
  // Closes the waveforms and renames them over the path; rpu::Error naming it if they
  // could not be written. Without trace(), nothing.
  virtual void close_trace() = 0;
};

struct IuModelName {
  std::string format, isect;
};

// The (format, intersection mode) pairs built into this binary.
std::vector<IuModelName> iu_models();

// A fresh model with registers and X initialised from `seed`; nullptr if not built.
std::unique_ptr<IuModel> make_iu_model(std::string_view format, std::string_view isect, std::uint64_t seed);

}  // namespace rpu::sim
