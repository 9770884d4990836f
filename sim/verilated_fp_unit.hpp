#pragma once

#include <verilated.h>

#include <cstdint>
#include <memory>

#include "fp_unit_model.hpp"

namespace rpu::sim {

// FpUnitModel over any Verilated rpu_fp_cosim_top (one class per unit and format).
template <class Top>
class VerilatedFpUnit final : public FpUnitModel {
 public:
  explicit VerilatedFpUnit(std::uint64_t seed) : context_(std::make_unique<VerilatedContext>()) {
    // Random initial values and X assignments, reproducible from the seed.
    context_->randReset(2);
    context_->randSeed(static_cast<int>(seed & 0x7fffffff));
    top_ = std::make_unique<Top>(context_.get());
    top_->clk_i = 0;
  }
  ~VerilatedFpUnit() override { top_->final(); }
  VerilatedFpUnit(const VerilatedFpUnit&) = delete;
  VerilatedFpUnit& operator=(const VerilatedFpUnit&) = delete;

  FpUnitOutputs settle(const FpUnitInputs& in) override {
    top_->rst_ni = in.rst_n;
    top_->req_valid_i = in.req_valid;
    top_->req_op_i = in.req_op;
    top_->req_tag_i = in.req_tag;
    top_->req_a_i = in.req_a;
    top_->req_b_i = in.req_b;
    top_->req_c_i = in.req_c;
    top_->rsp_ready_i = in.rsp_ready;
    top_->eval();
    return {top_->req_ready_o != 0, top_->rsp_valid_o != 0, top_->rsp_tag_o, top_->rsp_result_o};
  }

  void clock() override {
    top_->clk_i = 1;
    top_->eval();
    top_->clk_i = 0;
    top_->eval();
  }

 private:
  std::unique_ptr<VerilatedContext> context_;
  std::unique_ptr<Top> top_;
};

}  // namespace rpu::sim
