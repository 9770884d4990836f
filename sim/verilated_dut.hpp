#pragma once

#include <verilated.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>

#include "common/error.hpp"
#include "fst_output.hpp"

// The Verilator side of the harness core (sim/cosim_core.hpp): a Verilated top with its
// registers and X values random but reproducible from a seed (Verilator --x-assign
// unique --x-initial unique, STYLE.md 7), the clock, FST waveforms of every evaluation
// on request, and the copy of a stream between its flat port and its words.
namespace rpu::sim {

// How a harness's Inputs and Outputs (rpu/harness/<name>.hpp) reach a Verilated top's
// ports: each harness's specialisation is generated (rpu/harness/<name>_binding.hpp).
template <class Ports>
struct Binding;

// A stream's words into a flat port of its width: Verilator keeps a port of up to 32
// bits in one integer, up to 64 in a 64-bit one and wider ones as 32-bit words, bit k
// in bit k % 32 of word k / 32 as rpu::streams packs it.
template <class Port, std::size_t N>
void to_port(Port& port, const std::array<std::uint32_t, N>& words) {
  if constexpr (std::is_integral_v<Port>) {
    static_assert(N <= 2 && sizeof(Port) * 8 >= 32 * N - 31, "port narrower than the stream");
    std::uint64_t v = words[0];
    if constexpr (N == 2) v |= std::uint64_t{words[1]} << 32;
    port = static_cast<Port>(v);
  } else {
    static_assert(sizeof(port.m_storage) / sizeof(port.m_storage[0]) == N, "port and stream differ in width");
    for (std::size_t i = 0; i < N; ++i) port[i] = words[i];
  }
}

template <class Stream, class Port>
Stream from_port(const Port& port) {
  typename Stream::Words words{};
  if constexpr (std::is_integral_v<Port>) {
    static_assert(Stream::kWords <= 2 && sizeof(Port) * 8 >= Stream::kBits, "port narrower than the stream");
    const auto v = static_cast<std::uint64_t>(port);
    words[0] = static_cast<std::uint32_t>(v);
    if constexpr (Stream::kWords == 2) words[1] = static_cast<std::uint32_t>(v >> 32);
  } else {
    static_assert(sizeof(port.m_storage) / sizeof(port.m_storage[0]) == Stream::kWords,
                  "port and stream differ in width");
    for (std::size_t i = 0; i < words.size(); ++i) words[i] = port[i];
  }
  return Stream::unpack(words);
}

namespace detail {

// Copies n bits from src (from bit src_lsb) into dst (from bit dst_lsb), both arrays of
// 32-bit words with bit k in bit k % 32 of word k / 32.
inline void copy_bits(std::uint32_t* dst, std::size_t dst_lsb, const std::uint32_t* src, std::size_t src_lsb,
                      std::size_t n) {
  for (std::size_t i = 0; i < n;) {
    const std::size_t d = dst_lsb + i, s = src_lsb + i;
    const std::size_t chunk = std::min({32 - d % 32, 32 - s % 32, n - i});
    const std::uint32_t mask = chunk == 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << chunk) - 1;
    const std::uint32_t bits = (src[s / 32] >> (s % 32)) & mask;
    dst[d / 32] = (dst[d / 32] & ~(mask << (d % 32))) | (bits << (d % 32));
    i += chunk;
  }
}

}  // namespace detail

// Stream `index` of a flat port holding several streams S back to back, stream k at bits
// [k * S::kBits, (k + 1) * S::kBits): the co-simulation tops' ports of many requesters.
template <class S, class Port>
void to_port_at(Port& port, std::size_t index, const S& value) {
  const typename S::Words words = value.pack();
  const std::size_t lsb = index * static_cast<std::size_t>(S::kBits);
  if constexpr (std::is_integral_v<Port>) {
    const auto v = static_cast<std::uint64_t>(port);
    std::uint32_t w[2] = {static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(v >> 32)};
    detail::copy_bits(w, lsb, words.data(), 0, S::kBits);
    port = static_cast<Port>(std::uint64_t{w[0]} | (std::uint64_t{w[1]} << 32));
  } else {
    detail::copy_bits(port.m_storage, lsb, words.data(), 0, S::kBits);
  }
}

template <class S, class Port>
S from_port_at(const Port& port, std::size_t index) {
  typename S::Words words{};
  const std::size_t lsb = index * static_cast<std::size_t>(S::kBits);
  if constexpr (std::is_integral_v<Port>) {
    const auto v = static_cast<std::uint64_t>(port);
    const std::uint32_t w[2] = {static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(v >> 32)};
    detail::copy_bits(words.data(), 0, w, lsb, S::kBits);
  } else {
    detail::copy_bits(words.data(), 0, port.m_storage, lsb, S::kBits);
  }
  return S::unpack(words);
}

// A scalar port (a bit or a vector of up to 64 bits) from a value of the harness's.
template <class Port, class Value>
void set_port(Port& port, Value value) {
  static_assert(std::is_integral_v<Port>, "a vector wider than 64 bits is not a scalar port");
  port = static_cast<Port>(value);
}

// A scalar output port's value.
template <class Port>
std::uint64_t port_value(const Port& port) {
  static_assert(std::is_integral_v<Port>, "a vector wider than 64 bits is not a scalar port");
  return static_cast<std::uint64_t>(port);
}

// A [N-1:0] port of one bit per side-by-side stream, bit k from bits[k]; bits past the
// port's storage do not exist in this model (fewer cores than the harness's most).
template <class Port, std::size_t N>
void set_bits(Port& port, const std::array<bool, N>& bits) {
  static_assert(std::is_integral_v<Port>, "a bit per stream, at most 64");
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < N && i < 8 * sizeof(Port); ++i) v |= std::uint64_t{bits[i]} << i;
  port = static_cast<Port>(v);
}

template <class Port, std::size_t N>
void get_bits(const Port& port, std::array<bool, N>& bits) {
  static_assert(std::is_integral_v<Port>, "a bit per stream, at most 64");
  for (std::size_t i = 0; i < N; ++i) bits[i] = i < 8 * sizeof(Port) && ((static_cast<std::uint64_t>(port) >> i) & 1);
}

// How many streams S a port of side-by-side streams holds: its storage is its width
// rounded up to whole words, which leaves less than one stream over when S has at
// least 32 bits.
template <class S, class Port>
constexpr std::size_t port_streams(const Port& port) {
  static_assert(S::kBits >= 32, "a narrower stream would leave its count ambiguous in the port's storage");
  if constexpr (std::is_integral_v<Port>) {
    return 8 * sizeof(Port) / static_cast<std::size_t>(S::kBits);
  } else {
    return 8 * sizeof(port.m_storage) / static_cast<std::size_t>(S::kBits);
  }
}

// A Verilated top built with TRACE_FST has trace(); the others cannot write waveforms.
template <class Top>
inline constexpr bool kHasFst = requires(Top& t, VerilatedFstC* f) { t.trace(f, 0); };

template <class Top>
class VerilatedDut {
 public:
  // Waveforms to `fst` unless it is empty; rpu::Error if the top was built without them.
  VerilatedDut(std::uint64_t seed, const std::string& fst) : context_(std::make_unique<VerilatedContext>()) {
    context_->randReset(2);
    context_->randSeed(static_cast<int>(seed & 0x7fffffff));
    if (!fst.empty()) context_->traceEverOn(true);
    top_ = std::make_unique<Top>(context_.get());
    top_->clk_i = 0;
    if (!fst.empty()) {
      if constexpr (kHasFst<Top>) {
        fst_ = std::make_unique<FstOutput>(*top_, fst);
      } else {
        throw Error(fst + ": this model was built without FST waveforms (the ci tier builds them into the models "
                          "its tests trace only; RPU_COSIM_TIER=full builds them into all: docs/rtl.md, Tiers)");
      }
    }
  }
  ~VerilatedDut() {
    // Verilator tears a model's scopes down through the thread's current context, which
    // is the last one made: another model's, maybe gone by now (the shrinker makes and
    // drops many), so this one's first.
    Verilated::threadContextp(context_.get());
    top_->final();
    top_.reset();
  }
  VerilatedDut(const VerilatedDut&) = delete;
  VerilatedDut& operator=(const VerilatedDut&) = delete;

  Top& top() { return *top_; }

  void eval() {
    Verilated::threadContextp(context_.get());  // as in the destructor: several models may be alive
    top_->eval();
    if constexpr (kHasFst<Top>) {
      if (fst_ && time_ / 2 >= wave_begin_ && time_ / 2 < wave_end_) fst_->dump(time_);
    }
    ++time_;
  }

  // Waveforms of the clock cycles [begin, end) only (counted from the model's first
  // evaluation, reset included): FST of every cycle of a frame costs ~25x.
  void set_wave_window(std::uint64_t begin, std::uint64_t end) {
    wave_begin_ = begin;
    wave_end_ = end;
  }

  void clock() {
    top_->clk_i = 1;
    eval();
    top_->clk_i = 0;
    eval();
  }

  // Closes the waveforms and renames them over their path (FstOutput::close).
  void close_trace() {
    if constexpr (kHasFst<Top>) {
      if (fst_) fst_->close();
    }
  }

 private:
  std::unique_ptr<VerilatedContext> context_;
  std::unique_ptr<Top> top_;
  // Only traced tops hold a writer: the others are linked without the FST library.
  std::conditional_t<kHasFst<Top>, std::unique_ptr<FstOutput>, std::monostate> fst_;
  std::uint64_t time_ = 0;
  std::uint64_t wave_begin_ = 0, wave_end_ = ~std::uint64_t{0};
};

}  // namespace rpu::sim
