#pragma once

#include <cstdint>
#include <string>

#include "iu_model.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// IuModel over any Verilated rpu_iu_cosim_top (one class per format and mode).
template <class Top>
class VerilatedIu final : public IuModel {
 public:
  VerilatedIu(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  IuOutputs settle(const IuInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    t.req_valid_i = in.req_valid;
    to_port(t.req_i, in.req.pack());
    t.rsp_ready_i = in.rsp_ready;
    dut_.eval();
    return {t.req_ready_o != 0, t.rsp_valid_o != 0, from_port<streams::IuRsp>(t.rsp_o)};
  }

  void clock() override { dut_.clock(); }
  void close_trace() override { dut_.close_trace(); }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
