#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "progen/fault_class.hpp"
#include "progen/runner.hpp"

// What random programs exercised on the functional model, counted step by step: every
// instruction of spec/isa.toml, source modifiers and swizzle kinds per source, write
// masks, special registers, loads and stores by segment, divergence and
// reconvergence, loops, nested and indirect calls, rays that hit and miss, and the
// fault classes runs ended in (docs/random-programs.md "Coverage").
namespace rpu::progen {

class Coverage final : public StepObserver {
 public:
  struct Item {
    std::string_view group;
    std::string name;
    std::uint64_t count = 0;
  };

  Coverage();

  void start_chunk(const functional::ShaderCore::Chunk& chunk) override;
  void before_step(const functional::ShaderCore::Chunk& chunk) override;
  void after_step(const functional::StepRecord& record, const functional::ShaderCore::Chunk& chunk) override;
  // How the run ended: a program that halted, or the class of its fault's message.
  void add_outcome(const Outcome& outcome);

  Coverage& operator+=(const Coverage& other);

  const std::vector<Item>& items() const { return items_; }
  std::uint64_t count(std::string_view group, std::string_view name) const;
  std::uint64_t programs() const { return programs_; }
  // "group: name" of every item never seen; the fault classes only with `faults`.
  std::vector<std::string> missing(bool faults = true) const;
  // Every instruction, modifier, mask and event class seen (and, with `faults`, every
  // fault class).
  bool complete(bool faults = true) const { return missing(faults).empty(); }
  // A table of every item and its count, missing ones marked.
  std::string report(bool faults = true) const;

 private:
  int add(std::string_view group, std::string name);
  void bump(int item, std::uint64_t n = 1) { items_[static_cast<std::size_t>(item)].count += n; }

  std::vector<Item> items_;
  std::uint64_t programs_ = 0, halted_ = 0, faulted_ = 0;

  // Item indices (-1: none).
  std::array<int, 128> instruction_{};
  std::array<std::array<int, 3>, 3> modifier_{};  // [source][neg, abs, both]
  std::array<std::array<int, 4>, 3> swizzle_{};   // [source][identity, broadcast, permutation, other]
  std::array<int, 16> mask_{};
  std::vector<int> special_;                     // by index
  std::array<std::array<int, 4>, 4> load_{};      // [ld, ldf, ld1, ld1f][image, launch, data, framebuffer]
  std::array<int, 2> store_{};                    // st, st1 to the own pixel
  int divergent_ = 0, reconverged_ = 0, branch_split_ = 0, backward_ = 0, nested_call_ = 0, calli_split_ = 0,
      early_halt_ = 0;
  std::array<int, 4> ray_{};                      // trace hit, trace miss, tracea hit, tracea miss
  std::array<int, 32> fault_{};                   // by FaultClass
  std::uint64_t unclassified_ = 0;  // fault messages of no class (a model change to look at)

  // The chunk being run.
  std::uint32_t live_ = 0;
  bool diverged_ = false;
};

}  // namespace rpu::progen
