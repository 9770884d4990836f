#pragma once

#include <verilated.h>

#include <cstdint>
#include <memory>
#include <string>

#include "fst_output.hpp"
#include "iu_model.hpp"

namespace rpu::sim {

// IuModel over any Verilated rpu_iu_cosim_top (one class per format and mode).
template <class Top>
class VerilatedIu final : public IuModel {
 public:
  explicit VerilatedIu(std::uint64_t seed) : context_(std::make_unique<VerilatedContext>()) {
    // Random initial values and X assignments, reproducible from the seed.
    context_->randReset(2);
    context_->randSeed(static_cast<int>(seed & 0x7fffffff));
    top_ = std::make_unique<Top>(context_.get());
    top_->clk_i = 0;
  }
  ~VerilatedIu() override { top_->final(); }
  VerilatedIu(const VerilatedIu&) = delete;
  VerilatedIu& operator=(const VerilatedIu&) = delete;

  IuOutputs settle(const IuInputs& in) override {
    top_->rst_ni = in.rst_n;
    top_->req_valid_i = in.req_valid;
    top_->req_tag_i = in.tag;
    for (int i = 0; i < 3; ++i) {
      top_->req_origin_i[i] = in.origin[i];
      top_->req_direction_i[i] = in.direction[i];
    }
    top_->req_t_min_i = in.t_min;
    top_->req_t_best_i = in.t_best;
    top_->req_kx_i = in.kx;
    top_->req_ky_i = in.ky;
    top_->req_kz_i = in.kz;
    top_->req_shear_x_i = in.shear[0];
    top_->req_shear_y_i = in.shear[1];
    for (int i = 0; i < 12; ++i) top_->req_record_i[i] = in.record[i];
    top_->rsp_ready_i = in.rsp_ready;
    eval();
    return {top_->req_ready_o != 0, top_->rsp_valid_o != 0, top_->rsp_tag_o, top_->rsp_hit_o != 0,
            top_->rsp_t_o, top_->rsp_u_o, top_->rsp_v_o};
  }

  void clock() override {
    top_->clk_i = 1;
    eval();
    top_->clk_i = 0;
    eval();
  }

  void trace(const std::string& path) override {
    context_->traceEverOn(true);
    fst_ = std::make_unique<FstOutput>(*top_, path);
  }

  void close_trace() override {
    if (fst_) fst_->close();
  }

 private:
  void eval() {
    top_->eval();
    if (fst_) fst_->dump(time_++);
  }

  std::unique_ptr<VerilatedContext> context_;
  std::unique_ptr<Top> top_;
  std::unique_ptr<FstOutput> fst_;
  std::uint64_t time_ = 0;
};

}  // namespace rpu::sim
