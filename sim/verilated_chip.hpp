#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>

#include "chip_model.hpp"
#include "port_vectors.hpp"
#include "verilated_dut.hpp"

namespace rpu::sim {

// Stream `S` number `index` from a flat port holding several, number i at bits
// [i * S::kBits, +S::kBits) (each core's records, each unit's counters).
template <class S, class Port>
S stream_slice(const Port& port, int index) {
  // The port's 32-bit words: Verilator keeps up to 64 bits in one integer.
  const auto word_of = [&port](int w) -> std::uint32_t {
    if constexpr (std::is_integral_v<Port>) {
      return w < 2 ? static_cast<std::uint32_t>(static_cast<std::uint64_t>(port) >> (32 * w)) : 0;
    } else {
      return port[static_cast<std::size_t>(w)];
    }
  };
  typename S::Words words{};
  const int lsb = index * S::kBits;
  for (int b = 0; b < S::kBits; b += 32) {
    const int n = std::min(32, S::kBits - b);
    const int at = lsb + b, word = at / 32, shift = at % 32;
    std::uint64_t v = word_of(word) >> shift;
    if (shift + n > 32) v |= static_cast<std::uint64_t>(word_of(word + 1)) << (32 - shift);
    words[static_cast<std::size_t>(b / 32)] = static_cast<std::uint32_t>(v & (n == 32 ? 0xffffffffu : (1u << n) - 1));
  }
  return S::unpack(words);
}

// ChipModel over a Verilated rpu_chip_cosim_top of `kCores` cores, `kRayUnits` ray units
// and `kCodeWords` instructions of code memory.
template <class Top, int kCores, int kRayUnits, std::uint32_t kCodeWords>
class VerilatedChip final : public ChipModel {
 public:
  VerilatedChip(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  void clock() override { dut_.clock(); }
  int cores() const override { return kCores; }
  int ray_units() const override { return kRayUnits; }

  ChipCounters counters() override {
    Top& t = dut_.top();
    ChipCounters c;
    for (int k = 0; k < kCores; ++k) c.cores.push_back(stream_slice<streams::CoreCounters>(t.core_counters_o, k));
    for (int k = 0; k < kRayUnits; ++k) {
      c.ray_units.push_back(stream_slice<streams::RayUnitCounters>(t.ray_counters_o, k));
    }
    for (int k = 0; k < 2 + kCores; ++k) c.caches.push_back(stream_slice<streams::CacheCounters>(t.cache_counters_o, k));
    return c;
  }
  std::uint32_t code_words() const override { return kCodeWords; }
  void close_trace() override { dut_.close_trace(); }
  void set_wave_window(std::uint64_t begin, std::uint64_t end) override { dut_.set_wave_window(begin, end); }

  ChipOutputs settle(const ChipInputs& in) override {
    Top& t = dut_.top();
    t.rst_ni = in.rst_n;
    t.code_we_i = in.code_we;
    t.code_addr_i = in.code_addr;
    t.code_data_i = in.code_data;
    t.start_i = in.start;
    to_port(t.launch_i, in.launch.pack());
    to_port(t.tu_cfg_i, in.tu_cfg.pack());
    t.dram_req_ready_i = in.dram_req_ready;
    t.dram_rsp_valid_i = in.dram_rsp_valid;
    to_port(t.dram_rsp_i, in.dram_rsp.pack());
    dut_.eval();

    ChipOutputs out;
    out.done = t.done_o;
    out.dram_req_valid = t.dram_req_valid_o;
    out.dram_req = from_port<streams::DramReq>(t.dram_req_o);
    out.dram_rsp_ready = t.dram_rsp_ready_o;
    // Records only where valid: unpacking every core's every cycle would cost more
    // than the model.
    for (int c = 0; c < kCores; ++c) {
      CoreRecords& r = out.cores[static_cast<std::size_t>(c)];
      r.issue_valid = t.issue_valid_o >> c & 1;
      r.retire_valid = t.retire_valid_o >> c & 1;
      r.wb_valid = t.wb_valid_o >> c & 1;
      r.fault_valid = t.fault_valid_o >> c & 1;
      if (r.issue_valid) r.issue = stream_slice<streams::Issue>(t.issue_o, c);
      if (r.retire_valid) r.retire = stream_slice<streams::Retire>(t.retire_o, c);
      if (r.wb_valid) r.wb = stream_slice<streams::Writeback>(t.wb_o, c);
      if (r.fault_valid) r.fault = stream_slice<streams::Fault>(t.fault_o, c);
    }
    return out;
  }

  PortWords port_words() override {
    const Top& t = dut_.top();
    PortWords w;
    append_words(w.inputs, t.rst_ni);
    append_words(w.inputs, t.code_we_i);
    append_words(w.inputs, t.code_addr_i);
    append_words(w.inputs, t.code_data_i);
    append_words(w.inputs, t.start_i);
    append_words(w.inputs, t.launch_i);
    append_words(w.inputs, t.tu_cfg_i);
    append_words(w.inputs, t.dram_req_ready_i);
    append_words(w.inputs, t.dram_rsp_valid_i);
    append_words(w.inputs, t.dram_rsp_i);
    append_words(w.outputs, t.done_o);
    append_words(w.outputs, t.dram_req_valid_o);
    append_words(w.outputs, t.dram_req_o);
    append_words(w.outputs, t.dram_rsp_ready_o);
    append_words(w.outputs, t.issue_valid_o);
    append_words(w.outputs, t.issue_o);
    append_words(w.outputs, t.retire_valid_o);
    append_words(w.outputs, t.retire_o);
    append_words(w.outputs, t.wb_valid_o);
    append_words(w.outputs, t.wb_o);
    append_words(w.outputs, t.fault_valid_o);
    append_words(w.outputs, t.fault_o);
    append_words(w.outputs, t.core_counters_o);
    append_words(w.outputs, t.ray_counters_o);
    append_words(w.outputs, t.cache_counters_o);
    return w;
  }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
