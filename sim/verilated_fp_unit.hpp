#pragma once

#include <cstdint>
#include <string>

#include "fp_unit_model.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// FpUnitModel over any Verilated rpu_fp_cosim_top (one class per unit and format).
template <class Top>
class VerilatedFpUnit final : public FpUnitModel {
 public:
  VerilatedFpUnit(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  FpUnitOutputs settle(const FpUnitInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    t.req_valid_i = in.req_valid;
    to_port(t.req_i, in.req.pack());
    t.rsp_ready_i = in.rsp_ready;
    dut_.eval();
    return {t.req_ready_o != 0, t.rsp_valid_o != 0, from_port<streams::FpRsp>(t.rsp_o)};
  }

  void clock() override { dut_.clock(); }
  void close_trace() override { dut_.close_trace(); }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
