#pragma once

#include <cstdint>
#include <string>

#include "stream_unit_model.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// StreamUnitModel over a Verilated top with the ports rst_ni, req_valid_i, req_i,
// req_ready_o, rsp_valid_o, rsp_o and rsp_ready_i (one class per unit, format and mode).
template <class Top, class Req, class Rsp>
class VerilatedStreamUnit final : public StreamUnitModel<Req, Rsp> {
 public:
  using Inputs = typename StreamUnitModel<Req, Rsp>::Inputs;
  using Outputs = typename StreamUnitModel<Req, Rsp>::Outputs;

  VerilatedStreamUnit(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  Outputs settle(const Inputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    t.req_valid_i = in.req_valid;
    to_port(t.req_i, in.req.pack());
    t.rsp_ready_i = in.rsp_ready;
    dut_.eval();
    return {t.req_ready_o != 0, t.rsp_valid_o != 0, from_port<Rsp>(t.rsp_o)};
  }

  void clock() override { dut_.clock(); }
  void close_trace() override { dut_.close_trace(); }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
