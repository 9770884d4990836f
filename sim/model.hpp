#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "port_vectors.hpp"

// A Verilated co-simulation top behind a plain interface, so a harness needs no
// Verilator header: one interface for every harness of spec/harnesses.toml, whose
// generated rpu/harness/<name>.hpp gives the Ports (Inputs and Outputs structs). The
// models of a harness are built into one library per harness (sim/CMakeLists.txt,
// rpu_cosim_models), each with the facts it was built for.
namespace rpu::sim {

template <class Ports>
class Model {
 public:
  using Inputs = typename Ports::Inputs;
  using Outputs = typename Ports::Outputs;
  virtual ~Model() = default;
  // Applies the inputs with the clock low and returns the outputs they give, but the
  // on-demand ones (spec/harnesses.toml).
  virtual Outputs settle(const Inputs& in) = 0;
  // The on-demand outputs as the last settle or clock left them.
  virtual void read_on_demand(Outputs& out) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if they
  // could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
  // Waveforms of the cycles [begin, end) only (counted from the model's first cycle).
  virtual void set_wave_window(std::uint64_t begin, std::uint64_t end) = 0;
  // The ports as they are after the last settle(), in the top's port order (the
  // netlist testbenches' vectors, sim/port_vectors.hpp).
  virtual PortWords port_words() = 0;
};

// What a model was built as: its name (the Verilated prefix) and its facts, "key=value"
// words (config=tiny isect=woop cores=1 ...) that sim/CMakeLists.txt gives it.
class ModelInfo {
 public:
  constexpr ModelInfo(std::string_view name, std::string_view facts) : name_(name), facts_(facts) {}
  std::string_view name() const { return name_; }
  // The value of `key`; empty when the model has no such fact.
  std::string_view fact(std::string_view key) const;
  // A numeric fact; rpu::Error naming the model when it has none.
  int number(std::string_view key) const;
  // Whether every (key, value) pair is one of its facts.
  bool matches(std::initializer_list<std::pair<std::string_view, std::string_view>> wanted) const;
  // "key=value key=value", for messages listing what was built.
  std::string_view facts() const { return facts_; }

 private:
  std::string_view name_, facts_;
};

// The models of harness Ports this binary holds.
template <class Ports>
const std::vector<ModelInfo>& models();

// The model that has every wanted fact, or nullptr.
template <class Ports>
const ModelInfo* find_model(std::initializer_list<std::pair<std::string_view, std::string_view>> wanted) {
  for (const ModelInfo& m : models<Ports>()) {
    if (m.matches(wanted)) return &m;
  }
  return nullptr;
}

// A fresh model with every register and X initialised from `seed` (Verilator
// --x-assign unique --x-initial unique); waveforms to `fst` unless it is empty.
template <class Ports>
std::unique_ptr<Model<Ports>> make_model(const ModelInfo& which, std::uint64_t seed, const std::string& fst);

// "a, b, c": the facts of every model of Ports, for an error that names what was built.
template <class Ports>
std::string built_models() {
  std::string s;
  for (const ModelInfo& m : models<Ports>()) s += (s.empty() ? "" : ", ") + std::string(m.facts());
  return s.empty() ? "none" : s;
}

// A model that also writes the ports of every settle() out of reset once started (the
// vectors a netlist testbench replays after its own reset, one clock each).
template <class Ports>
class RecordingModel final : public Model<Ports> {
 public:
  using typename Model<Ports>::Inputs;
  using typename Model<Ports>::Outputs;
  RecordingModel(std::unique_ptr<Model<Ports>> inner, std::ostream& out) : inner_(std::move(inner)), writer_(out) {}
  void start() { started_ = true; }
  std::uint64_t cycles() const { return cycles_; }

  Outputs settle(const Inputs& in) override {
    Outputs out = inner_->settle(in);
    if (started_ && in.rst_n) {
      writer_.write(inner_->port_words());
      ++cycles_;
    }
    return out;
  }
  void read_on_demand(Outputs& out) override { inner_->read_on_demand(out); }
  void clock() override { inner_->clock(); }
  void close_trace() override { inner_->close_trace(); }
  void set_wave_window(std::uint64_t begin, std::uint64_t end) override { inner_->set_wave_window(begin, end); }
  PortWords port_words() override { return inner_->port_words(); }

 private:
  std::unique_ptr<Model<Ports>> inner_;
  VectorWriter writer_;
  bool started_ = false;
  std::uint64_t cycles_ = 0;
};

}  // namespace rpu::sim
