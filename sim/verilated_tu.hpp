#pragma once

#include <verilated.h>

#include <cstdint>
#include <memory>
#include <string>

#include "fst_output.hpp"
#include "tu_model.hpp"

namespace rpu::sim {

template <class Wide>
void set_words(Wide& port, const auto& words) {
  for (std::size_t i = 0; i < words.size(); ++i) port[i] = words[i];
}

// TuModel over a Verilated rpu_tu_cosim_top: the TU alone (WithIu = 0), whose IU port
// the harness serves, or the ray unit (WithIu = 1), whose IU port pins are tied off.
template <class Top, bool kWithIu>
class VerilatedTu final : public TuModel {
  static constexpr bool kIuPort = !kWithIu;

 public:
  VerilatedTu(std::uint64_t seed, const std::string& fst) : context_(std::make_unique<VerilatedContext>()) {
    // Random initial values and X assignments, reproducible from the seed.
    context_->randReset(2);
    context_->randSeed(static_cast<int>(seed & 0x7fffffff));
    if (!fst.empty()) context_->traceEverOn(true);
    top_ = std::make_unique<Top>(context_.get());
    top_->clk_i = 0;
    if (!fst.empty()) trace_ = std::make_unique<FstOutput>(*top_, fst);
  }
  ~VerilatedTu() override { top_->final(); }
  VerilatedTu(const VerilatedTu&) = delete;
  VerilatedTu& operator=(const VerilatedTu&) = delete;

  bool has_iu_port() const override { return kIuPort; }

  void close_trace() override {
    if (trace_) trace_->close();
  }

  TuOutputs settle(const TuInputs& in) override {
    Top& t = *top_;
    t.rst_ni = in.rst_n;
    t.cfg_kd_nodes_i = in.kd_nodes;
    t.cfg_prim_refs_i = in.prim_refs;
    t.cfg_isect_records_i = in.isect_records;
    set_words(t.cfg_bounds_lo_i, in.bounds_lo);
    set_words(t.cfg_bounds_hi_i, in.bounds_hi);
    t.cfg_kd_scale_exponent_i = static_cast<std::uint8_t>(in.kd_scale_exponent);
    t.req_valid_i = in.req_valid;
    t.req_tag_i = in.req_tag;
    set_words(t.req_origin_i, in.origin);
    set_words(t.req_direction_i, in.direction);
    t.req_t_min_i = in.t_min;
    t.req_t_max_i = in.t_max;
    t.req_any_hit_i = in.any_hit;
    t.rsp_ready_i = in.rsp_ready;
    t.mem_req_ready_i = in.mem_req_ready;
    t.mem_rsp_valid_i = in.mem_rsp_valid;
    set_words(t.mem_rsp_data_i, in.mem_rsp_data);
    if constexpr (kIuPort) {
      t.iu_req_ready_i = in.iu_req_ready;
      t.iu_rsp_valid_i = in.iu_rsp_valid;
      t.iu_rsp_tag_i = in.iu_rsp.tag;
      t.iu_rsp_hit_i = in.iu_rsp.hit;
      t.iu_rsp_t_i = in.iu_rsp.t;
      t.iu_rsp_u_i = in.iu_rsp.u;
      t.iu_rsp_v_i = in.iu_rsp.v;
    }
    t.eval();
    if (trace_) trace_->dump(2 * cycle_);

    TuOutputs out;
    out.req_ready = t.req_ready_o;
    out.rsp_valid = t.rsp_valid_o;
    out.tag = t.rsp_tag_o;
    out.hit = t.rsp_hit_o;
    out.t = t.rsp_t_o;
    out.u = t.rsp_u_o;
    out.v = t.rsp_v_o;
    out.prim = t.rsp_prim_o;
    out.nodes = t.rsp_nodes_o;
    out.leaves = t.rsp_leaves_o;
    out.tests = t.rsp_tests_o;
    out.fault = t.rsp_fault_o;
    out.mem_req_valid = t.mem_req_valid_o;
    out.mem_req_addr = t.mem_req_addr_o;
    out.mem_rsp_ready = t.mem_rsp_ready_o;
    if constexpr (kIuPort) {
      out.iu_req_valid = t.iu_req_valid_o;
      out.iu_rsp_ready = t.iu_rsp_ready_o;
      TuIuRequest& r = out.iu_req;
      r.tag = t.iu_req_tag_o;
      for (int i = 0; i < 3; ++i) {
        r.origin[i] = t.iu_req_origin_o[i];
        r.direction[i] = t.iu_req_direction_o[i];
      }
      r.shear = {static_cast<std::uint32_t>(t.iu_req_shear_o), static_cast<std::uint32_t>(t.iu_req_shear_o >> 32)};
      r.t_min = t.iu_req_t_min_o;
      r.t_best = t.iu_req_t_best_o;
      r.kx = t.iu_req_axes_o & 3;
      r.ky = (t.iu_req_axes_o >> 2) & 3;
      r.kz = (t.iu_req_axes_o >> 4) & 3;
      for (int i = 0; i < 12; ++i) r.record[i] = t.iu_req_record_o[i];
    }
    return out;
  }

  void clock() override {
    top_->clk_i = 1;
    top_->eval();
    if (trace_) trace_->dump(2 * cycle_ + 1);
    top_->clk_i = 0;
    top_->eval();
    ++cycle_;
  }

 private:
  std::unique_ptr<VerilatedContext> context_;
  std::unique_ptr<Top> top_;
  std::unique_ptr<FstOutput> trace_;
  std::uint64_t cycle_ = 0;
};

}  // namespace rpu::sim
