#pragma once

#include <cstdint>
#include <ostream>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

// The per-cycle vectors of a Verilated top's ports that rtl/flow.py's netlist
// testbenches replay (sim/rpu_mem_netlist_tb.sv, sim/rpu_chip_netlist_tb.sv): a line
// "<input words> <output words>", then per cycle the ports' 32-bit words, least
// significant first, inputs then outputs, in the top's port order.
namespace rpu::sim {

struct PortWords {
  std::vector<std::uint32_t> inputs, outputs;
};

// A Verilated port's words, least significant first (a port of up to 32 bits is one
// word, of up to 64 two, a wider one its VlWide words).
template <class Port>
void append_words(std::vector<std::uint32_t>& out, const Port& port) {
  if constexpr (std::is_integral_v<Port>) {
    const auto v = static_cast<std::uint64_t>(port);
    out.push_back(static_cast<std::uint32_t>(v));
    if constexpr (sizeof(Port) == 8) out.push_back(static_cast<std::uint32_t>(v >> 32));
  } else {
    for (std::size_t i = 0; i < sizeof(port.m_storage) / sizeof(port.m_storage[0]); ++i) out.push_back(port[i]);
  }
}

// Writes the header before the first cycle, then one line a cycle.
class VectorWriter {
 public:
  explicit VectorWriter(std::ostream& out) : out_(out) {}
  void write(const PortWords& w) {
    if (!header_) {
      out_ << w.inputs.size() << ' ' << w.outputs.size() << '\n';
      header_ = true;
    }
    for (const std::uint32_t x : w.inputs) out_ << fmt::format("{:08x} ", x);
    for (const std::uint32_t x : w.outputs) out_ << fmt::format("{:08x} ", x);
    out_ << '\n';
  }

 private:
  std::ostream& out_;
  bool header_ = false;
};

}  // namespace rpu::sim
