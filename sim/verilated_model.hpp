#pragma once

#include <cstdint>
#include <string>

#include "model.hpp"
#include "verilated_dut.hpp"

// Model over a Verilated top: the generated Binding<Ports> (rpu/harness/<name>_binding.hpp)
// copies the Inputs and Outputs to and from its ports. Included only by the models'
// registries (sim/models.cpp.in), which are compiled with Verilator's flags.
namespace rpu::sim {

template <class Top, class Ports>
class VerilatedModel final : public Model<Ports> {
 public:
  using typename Model<Ports>::Inputs;
  using typename Model<Ports>::Outputs;
  VerilatedModel(std::uint64_t seed, const std::string& fst) : dut_(seed, fst) {}

  Outputs settle(const Inputs& in) override {
    Binding<Ports>::write(dut_.top(), in);
    dut_.eval();
    Outputs out;
    Binding<Ports>::read(dut_.top(), out);
    return out;
  }
  void read_on_demand(Outputs& out) override { Binding<Ports>::read_on_demand(dut_.top(), out); }
  void clock() override { dut_.clock(); }
  void close_trace() override { dut_.close_trace(); }
  void set_wave_window(std::uint64_t begin, std::uint64_t end) override { dut_.set_wave_window(begin, end); }
  PortWords port_words() override { return Binding<Ports>::words(dut_.top()); }

 private:
  VerilatedDut<Top> dut_;
};

}  // namespace rpu::sim
