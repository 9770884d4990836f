#pragma once

#include <concepts>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

// The harness core every co-simulation shares (docs/rtl.md, "Harness core"): reset and
// clocking of a model, seeded random stalls, the no-progress time-out, the table that
// pairs responses with requests by tag, the leftover checks at the end and the
// first-mismatch report of a stream compared field by field. A harness brings only its
// agents (memory server, IU server) and what it compares; the Verilator side (seeded
// initial values, FST waveforms, the flat ports) is sim/verilated_dut.hpp.
namespace rpu::sim {

// A check that failed; the harness prints "<harness> FAIL: <what>" and exits with 1.
class CosimFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A model the harness drives: settle() applies the inputs with the clock low and returns
// the outputs they give; clock() is one rising and one falling edge.
template <class M>
concept ClockedDut = requires(M& m, const typename M::Inputs& in) {
  { m.settle(in) } -> std::same_as<typename M::Outputs>;
  m.clock();
};

// A model with its cycle count.
template <ClockedDut M>
class Clock {
 public:
  using Inputs = typename M::Inputs;
  using Outputs = typename M::Outputs;

  explicit Clock(M& model) : model_(model) {}

  // `cycles` clocks with rst_n low and `in` applied, then rst_n high in `in`. Reset
  // cycles are not counted.
  void reset(Inputs& in, int cycles = 4) {
    in.rst_n = false;
    for (int i = 0; i < cycles; ++i) {
      model_.settle(in);
      model_.clock();
    }
    in.rst_n = true;
  }

  Outputs settle(const Inputs& in) { return model_.settle(in); }
  void tick() {
    model_.clock();
    ++cycle_;
  }
  std::uint64_t cycle() const { return cycle_; }

 private:
  M& model_;
  std::uint64_t cycle_ = 0;
};

// Random stalls of valids and readies, reproducible from the seed: each call is a stall
// with probability p. rng() is the same stream, for the agents' random delays.
class Stalls {
 public:
  Stalls(std::uint64_t seed, double p) : rng_(seed), stall_(p) {}
  bool operator()() { return stall_(rng_); }
  std::mt19937_64& rng() { return rng_; }

 private:
  std::mt19937_64 rng_;
  std::bernoulli_distribution stall_;
};

// Fails when a response is owed and none came for `limit` cycles.
class Watchdog {
 public:
  explicit Watchdog(std::uint64_t limit) : limit_(limit) {}
  void progress(std::uint64_t cycle) { last_ = cycle; }
  // `what()` describes the oldest owed transaction for the message.
  template <class Describe>
  void check(std::uint64_t cycle, bool owed, Describe&& what) {
    if (!owed) {
      last_ = cycle;
    } else if (cycle - last_ > limit_) {
      throw CosimFailure("no response for " + std::to_string(limit_) + " cycles at cycle " + std::to_string(cycle) +
                         ": " + std::string(what()));
    }
  }

 private:
  std::uint64_t limit_, last_ = 0;
};

inline std::string hex(std::uint32_t v, int bits) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%0*x", (bits + 3) / 4, v);
  return text;
}

// The requests in flight, keyed by tag: answers may come in any order. A request whose
// tag is still in flight, an answer with a tag nobody is waiting for and, at the end,
// a request never answered are failures naming the stream and the tag.
template <class T>
class PendingByTag {
 public:
  PendingByTag(std::string_view request, std::string_view response, int tag_bits)
      : request_(request), response_(response), tag_bits_(tag_bits) {}

  void add(std::uint32_t tag, T value) {
    if (!table_.emplace(tag, Entry{std::move(value), serial_++}).second) {
      throw CosimFailure(request_ + " with tag " + hex(tag, tag_bits_) + " sent while that tag is in flight");
    }
  }

  T* find(std::uint32_t tag) {
    const auto it = table_.find(tag);
    return it == table_.end() ? nullptr : &it->second.value;
  }
  const T* find(std::uint32_t tag) const {
    const auto it = table_.find(tag);
    return it == table_.end() ? nullptr : &it->second.value;
  }

  T take(std::uint32_t tag) {
    const auto it = table_.find(tag);
    if (it == table_.end()) {
      throw CosimFailure(response_ + " with tag " + hex(tag, tag_bits_) + " answers no " + request_ + " in flight (" +
                         std::to_string(table_.size()) + " in flight)");
    }
    T value = std::move(it->second.value);
    table_.erase(it);
    return value;
  }

  bool empty() const { return table_.empty(); }
  std::size_t size() const { return table_.size(); }

  // The request in flight longest; the table must not be empty.
  const T& oldest() const {
    auto best = table_.begin();
    for (auto it = table_.begin(); it != table_.end(); ++it) {
      if (it->second.serial < best->second.serial) best = it;
    }
    return best->second.value;
  }

  // The end of a run: every request answered. `describe(value)` names the oldest left.
  template <class Describe>
  void check_empty(Describe&& describe) const {
    if (!empty()) {
      throw CosimFailure(std::to_string(size()) + " " + request_ + "(s) never answered; the oldest: " +
                         std::string(describe(oldest())));
    }
  }

 private:
  struct Entry {
    T value;
    std::uint64_t serial;
  };
  std::string request_, response_;
  int tag_bits_;
  std::map<std::uint32_t, Entry> table_;
  std::uint64_t serial_ = 0;
};

// After the last answer: `cycles` more clocks with `idle` applied (no request, every
// ready high); `leftover(outputs)` names a valid output, which would be a transaction
// nobody asked for, or returns "".
template <ClockedDut M, class Leftover>
void expect_quiet(Clock<M>& clock, const typename M::Inputs& idle, int cycles, Leftover&& leftover) {
  for (int i = 0; i < cycles; ++i) {
    const std::string what = leftover(clock.settle(idle));
    if (!what.empty()) {
      throw CosimFailure(what + " at cycle " + std::to_string(clock.cycle()) + ", after every transaction was done");
    }
    clock.tick();
  }
}

// A stream value with every field's bits set: compare in all of them.
template <class S>
S all_fields() {
  typename S::Words w;
  w.fill(~std::uint32_t{0});
  return S::unpack(w);
}

// "" if `got` equals `expected` in every bit `care` sets; else a report that names the
// first field that differs, then lists every field (expected, got; fields outside
// `care` marked so), in the stream's order (spec/streams.toml).
template <class S>
std::string field_mismatch(const S& expected, const S& got, const S& care) {
  const auto e = expected.fields(), g = got.fields(), c = care.fields();
  // Compared before anything is formatted: a run checks every answer, and the report is
  // for the one that fails.
  bool any = false;
  for (std::size_t i = 0; i < e.size(); ++i) {
    for (int k = 0; k < e[i].count; ++k) {
      any |= ((e[i].words[k] ^ g[i].words[k]) & c[i].words[k]) != 0;
    }
  }
  if (!any) {
    return "";
  }
  std::string first, table;
  for (std::size_t i = 0; i < e.size(); ++i) {
    std::string want, have;
    bool differs = false, cared = false;
    for (int k = 0; k < e[i].count; ++k) {
      const std::uint32_t m = c[i].words[k];
      cared |= m != 0;
      differs |= ((e[i].words[k] ^ g[i].words[k]) & m) != 0;
      // Word 0 last: a vector reads as one number, as the SV field does.
      want = hex(e[i].words[k], e[i].bits) + (k ? " " : "") + want;
      have = hex(g[i].words[k], g[i].bits) + (k ? " " : "") + have;
    }
    if (differs && first.empty()) {
      first = std::string(S::kName) + "." + std::string(e[i].name) + ": expected " + want + ", got " + have;
    }
    table += "\n    " + std::string(e[i].name) + (differs ? " (differs)" : cared ? "" : " (not compared)") +
             ": expected " + want + ", got " + have;
  }
  return first + table;
}

template <class S>
std::string field_mismatch(const S& expected, const S& got) {
  return field_mismatch(expected, got, all_fields<S>());
}

}  // namespace rpu::sim
