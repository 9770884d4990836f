#pragma once

#include <cstdint>
#include <string>

#include "tu_model.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// TuModel over a Verilated rpu_tu_cosim_top: the TU alone (WithIu = 0), whose IU port
// the harness serves, or the ray unit (WithIu = 1), whose IU port pins are tied off.
template <class Top, bool kWithIu>
class VerilatedTu final : public TuModel {
  static constexpr bool kIuPort = !kWithIu;

 public:
  VerilatedTu(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  bool has_iu_port() const override { return kIuPort; }
  void close_trace() override { dut_.close_trace(); }
  void clock() override { dut_.clock(); }

  TuOutputs settle(const TuInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    to_port(t.cfg_i, in.cfg.pack());
    t.req_valid_i = in.req_valid;
    to_port(t.req_i, in.req.pack());
    t.rsp_ready_i = in.rsp_ready;
    t.mem_req_ready_i = in.mem_req_ready;
    t.mem_rsp_valid_i = in.mem_rsp_valid;
    to_port(t.mem_rsp_i, in.mem_rsp.pack());
    if constexpr (kIuPort) {
      t.iu_req_ready_i = in.iu_req_ready;
      t.iu_rsp_valid_i = in.iu_rsp_valid;
      to_port(t.iu_rsp_i, in.iu_rsp.pack());
    }
    dut_.eval();

    TuOutputs out;
    out.req_ready = t.req_ready_o;
    out.rsp_valid = t.rsp_valid_o;
    out.rsp = from_port<streams::TuRsp>(t.rsp_o);
    out.mem_req_valid = t.mem_req_valid_o;
    out.mem_req = from_port<streams::MemReq>(t.mem_req_o);
    out.mem_rsp_ready = t.mem_rsp_ready_o;
    if constexpr (kIuPort) {
      out.iu_req_valid = t.iu_req_valid_o;
      out.iu_rsp_ready = t.iu_rsp_ready_o;
      out.iu_req = from_port<streams::IuReq>(t.iu_req_o);
    }
    return out;
  }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
