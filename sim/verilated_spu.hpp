#pragma once

#include <cstdint>
#include <string>

#include "spu_model.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// SpuModel over a Verilated rpu_spu_cosim_top of `kCodeWords` instructions.
template <class Top, std::uint32_t kCodeWords>
class VerilatedSpu final : public SpuModel {
 public:
  VerilatedSpu(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  void clock() override { dut_.clock(); }
  std::uint32_t code_words() const override { return kCodeWords; }
  void close_trace() override { dut_.close_trace(); }

  SpuOutputs settle(const SpuInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    t.code_we_i = in.code_we;
    t.code_addr_i = in.code_addr;
    t.code_data_i = in.code_data;
    t.start_i = in.start;
    to_port(t.launch_i, in.launch.pack());
    t.stop_i = in.stop;
    t.stop_pixel_i = in.stop_pixel;
    t.cache_req_ready_i = in.cache_req_ready;
    t.cache_rsp_valid_i = in.cache_rsp_valid;
    to_port(t.cache_rsp_i, in.cache_rsp.pack());
    t.trace_req_ready_i = in.trace_req_ready;
    t.trace_rsp_valid_i = in.trace_rsp_valid;
    to_port(t.trace_rsp_i, in.trace_rsp.pack());
    dut_.eval();

    SpuOutputs out;
    out.done = t.done_o;
    out.cache_req_valid = t.cache_req_valid_o;
    out.cache_req = from_port<streams::CacheReq>(t.cache_req_o);
    out.cache_rsp_ready = t.cache_rsp_ready_o;
    out.trace_req_valid = t.trace_req_valid_o;
    out.trace_req = from_port<streams::TraceReq>(t.trace_req_o);
    out.trace_rsp_ready = t.trace_rsp_ready_o;
    out.issue_valid = t.issue_valid_o;
    out.issue = from_port<streams::Issue>(t.issue_o);
    out.retire_valid = t.retire_valid_o;
    out.retire = from_port<streams::Retire>(t.retire_o);
    out.wb_valid = t.wb_valid_o;
    out.wb = from_port<streams::Writeback>(t.wb_o);
    out.fault_valid = t.fault_valid_o;
    out.fault = from_port<streams::Fault>(t.fault_o);
    return out;
  }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
