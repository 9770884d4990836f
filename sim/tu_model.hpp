#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

// One Verilated traversal unit (sim/rpu_tu_cosim_top.sv: the TU alone, its IU port
// open; or a top with the RTL IU inside) behind a plain interface, so the harness needs
// no Verilator header: the models are built in their own library.
namespace rpu::sim {

struct TuIuRequest {
  std::uint32_t tag = 0;
  std::array<std::uint32_t, 3> origin{}, direction{};
  std::uint32_t t_min = 0, t_best = 0;
  int kx = 0, ky = 1, kz = 2;
  std::array<std::uint32_t, 2> shear{};
  std::array<std::uint32_t, 12> record{};
};

struct TuIuResponse {
  std::uint32_t tag = 0;
  bool hit = false;
  std::uint32_t t = 0, u = 0, v = 0;
};

struct TuInputs {
  bool rst_n = false;
  std::uint32_t kd_nodes = 0, prim_refs = 0, isect_records = 0;
  std::array<std::uint32_t, 3> bounds_lo{}, bounds_hi{};
  std::int32_t kd_scale_exponent = 0;
  bool req_valid = false;
  std::uint32_t req_tag = 0;
  std::array<std::uint32_t, 3> origin{}, direction{};
  std::uint32_t t_min = 0, t_max = 0;
  bool any_hit = false;
  bool rsp_ready = false;
  bool mem_req_ready = false;
  bool mem_rsp_valid = false;
  std::array<std::uint32_t, 4> mem_rsp_data{};
  bool iu_req_ready = false;  // the IU port exists only without the RTL IU
  bool iu_rsp_valid = false;
  TuIuResponse iu_rsp;
};

struct TuOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  std::uint32_t tag = 0;
  bool hit = false;
  std::uint32_t t = 0, u = 0, v = 0, prim = 0, nodes = 0, leaves = 0, tests = 0;
  bool fault = false;
  bool mem_req_valid = false;
  std::uint32_t mem_req_addr = 0;
  bool mem_rsp_ready = false;
  bool iu_req_valid = false;
  TuIuRequest iu_req;
  bool iu_rsp_ready = false;
};

class TuModel {
 public:
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
};

// The models built into this binary.
std::vector<TuModelName> tu_models();

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty;
// nullptr if the model was not built.
std::unique_ptr<TuModel> make_tu_model(const TuModelName& name, std::uint64_t seed, const std::string& fst);

}  // namespace rpu::sim
