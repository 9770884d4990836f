#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "mem_model.hpp"
#include "port_vectors.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

namespace detail {

template <class Port, std::size_t N>
void set_bits(Port& port, const std::array<bool, N>& bits) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < N; ++i) v |= std::uint64_t{bits[i]} << i;
  port = static_cast<Port>(v);
}

template <std::size_t N, class Port>
std::array<bool, N> get_bits(const Port& port) {
  std::array<bool, N> bits{};
  for (std::size_t i = 0; i < N; ++i) bits[i] = (static_cast<std::uint64_t>(port) >> i) & 1;
  return bits;
}

}  // namespace detail

// MemModel over a Verilated rpu_mem_cosim_top.
template <class Top>
class VerilatedMem final : public MemModel {
 public:
  VerilatedMem(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {
    Top& t = dut_.top();
    static_assert(holds_streams<streams::CacheReq, kRaw, decltype(t.req_i)>(), "req_i is not kRaw cache_req");
    static_assert(holds_streams<streams::CacheRsp, kRaw, decltype(t.rsp_o)>(), "rsp_o is not kRaw cache_rsp");
    static_assert(holds_streams<streams::MemReq, kInOrder, decltype(t.mem_req_i)>(), "mem_req_i is not kInOrder");
    static_assert(holds_streams<streams::MemRsp, kInOrder, decltype(t.mem_rsp_o)>(), "mem_rsp_o is not kInOrder");
    static_assert(holds_streams<streams::CacheCounters, kMemCaches, decltype(t.counters_o)>(),
                  "counters_o is not kMemCaches cache_counters");
  }

  void clock() override { dut_.clock(); }
  void close_trace() override { dut_.close_trace(); }

  std::array<CacheGeometry, kMemCaches> geometry() override {
    dut_.eval();
    const Top& t = dut_.top();
    std::array<CacheGeometry, kMemCaches> g{};
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      g[c] = {t.geometry_o[4 * c], t.geometry_o[4 * c + 1], t.geometry_o[4 * c + 2], t.geometry_o[4 * c + 3]};
    }
    return g;
  }

  MemOutputs settle(const MemInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    detail::set_bits(t.req_valid_i, in.req_valid);
    detail::set_bits(t.rsp_ready_i, in.rsp_ready);
    for (std::size_t p = 0; p < kRaw; ++p) to_port_at(t.req_i, p, in.req[p]);
    detail::set_bits(t.mem_req_valid_i, in.mem_req_valid);
    detail::set_bits(t.mem_rsp_ready_i, in.mem_rsp_ready);
    for (std::size_t p = 0; p < kInOrder; ++p) to_port_at(t.mem_req_i, p, in.mem_req[p]);
    t.dram_req_ready_i = in.dram_req_ready;
    t.dram_rsp_valid_i = in.dram_rsp_valid;
    to_port(t.dram_rsp_i, in.dram_rsp.pack());
    dut_.eval();

    MemOutputs out;
    out.req_ready = detail::get_bits<kRaw>(t.req_ready_o);
    out.rsp_valid = detail::get_bits<kRaw>(t.rsp_valid_o);
    for (std::size_t p = 0; p < kRaw; ++p) out.rsp[p] = from_port_at<streams::CacheRsp>(t.rsp_o, p);
    out.mem_req_ready = detail::get_bits<kInOrder>(t.mem_req_ready_o);
    out.mem_rsp_valid = detail::get_bits<kInOrder>(t.mem_rsp_valid_o);
    for (std::size_t p = 0; p < kInOrder; ++p) out.mem_rsp[p] = from_port_at<streams::MemRsp>(t.mem_rsp_o, p);
    out.dram_req_valid = t.dram_req_valid_o;
    out.dram_req = from_port<streams::DramReq>(t.dram_req_o);
    out.dram_rsp_ready = t.dram_rsp_ready_o;
    for (std::size_t c = 0; c < kMemCaches; ++c) {
      out.counters[c] = from_port_at<streams::CacheCounters>(t.counters_o, c);
    }
    out.idle = detail::get_bits<kMemCaches>(t.idle_o);
    return out;
  }

  // In the order of the top's port list (sim/rpu_mem_netlist_tb.sv reads them so).
  PortWords port_words() override {
    const Top& t = dut_.top();
    PortWords w;
    append_words(w.inputs, t.rst_ni);
    append_words(w.inputs, t.req_valid_i);
    append_words(w.inputs, t.req_i);
    append_words(w.inputs, t.rsp_ready_i);
    append_words(w.inputs, t.mem_req_valid_i);
    append_words(w.inputs, t.mem_req_i);
    append_words(w.inputs, t.mem_rsp_ready_i);
    append_words(w.inputs, t.dram_req_ready_i);
    append_words(w.inputs, t.dram_rsp_valid_i);
    append_words(w.inputs, t.dram_rsp_i);
    append_words(w.outputs, t.req_ready_o);
    append_words(w.outputs, t.rsp_valid_o);
    append_words(w.outputs, t.rsp_o);
    append_words(w.outputs, t.mem_req_ready_o);
    append_words(w.outputs, t.mem_rsp_valid_o);
    append_words(w.outputs, t.mem_rsp_o);
    append_words(w.outputs, t.dram_req_valid_o);
    append_words(w.outputs, t.dram_req_o);
    append_words(w.outputs, t.dram_rsp_ready_o);
    append_words(w.outputs, t.counters_o);
    append_words(w.outputs, t.idle_o);
    return w;
  }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
