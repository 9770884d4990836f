#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "fp/format.hpp"
#include "fp/soft.hpp"
#include "oracle.hpp"

// Operands that reach every edge class of an operation, shared by the MPFR tests
// (test_fp.cpp) and the RTL co-simulation (sim/), so both check the same cases.
namespace rpu::fp {

using oracle::Op;
using oracle::OpInfo;

// Operands beyond the op's arity are ignored; from_fp32 takes fp32 bits in `a`,
// from_int32 the int32's bits.
struct Operands {
  std::uint32_t a, b, c;
};

// rpu::fp::soft's result for `op`, as a uint32 like oracle::expected().
std::uint32_t soft_result(Op op, Format f, const Operands& v);

// Values from every edge class of the format: zeros, subnormals (which must read as
// zero), the smallest normals and their neighbours, values around 1, the largest
// finite values, infinities and NaNs with various payloads and signs.
std::vector<std::uint32_t> edge_values(Format f);

// Cases that random operands rarely reach, built per format.
std::vector<Operands> constructed(Op op, Format f);

// Random operands that reach the interesting cases: uniform bit patterns, operands
// with nearby exponents (cancellation), sparse significands (exact results and
// ties), results near the overflow and underflow limits, and edge values.
class OperandSource {
 public:
  OperandSource(Op op, Format f, std::uint64_t seed) : op_(op), f_(f), rng_(seed), edges_(edge_values(f)) {}

  Operands next() {
    switch (op_) {
      case Op::kFromFp32: return {from_fp32_input(), 0, 0};
      case Op::kFromInt32: return {int32_input(), 0, 0};
      default: break;
    }
    const int kind = static_cast<int>(below(8));
    Operands v{value(), value(), value()};
    switch (kind) {
      case 0: break;  // uniform over the whole encoding
      case 1: {       // nearby exponents, either sign
        v.a = with_exponent(random_field(), random_sign());
        v.b = near(v.a, static_cast<int>(below(static_cast<std::uint64_t>(f_.fraction_bits) + 4)));
        v.c = op_ == Op::kFma ? near(soft::mul(f_, v.a, v.b), 3) : near(v.a, 2);
        break;
      }
      case 2: {  // (near) cancellation: b and c close to -a and -a*b
        v.a = with_exponent(random_field(), random_sign());
        v.b = perturb(v.a ^ f_.sign_mask());
        if (op_ == Op::kFma) {
          v.b = with_exponent(random_field(), random_sign());
          v.c = perturb(soft::mul(f_, v.a, v.b) ^ f_.sign_mask());
        }
        break;
      }
      case 3: {  // sparse significands: exact results and exact ties
        v.a = sparse(v.a);
        v.b = sparse(v.b);
        v.c = sparse(v.c);
        if (op_ == Op::kAdd || op_ == Op::kSub) v.b = sparse(near(v.a, 2 + static_cast<int>(below(4))));
        break;
      }
      case 4: {  // results near the largest finite value or the smallest normal
        const bool high = below(2) == 0;
        const int target = (high ? f_.max_exponent() : f_.min_exponent()) + static_cast<int>(below(4)) - 2;
        const int ea = static_cast<int>(random_field()) - f_.bias();
        const int eb = op_ == Op::kDiv ? ea - target : target - ea;
        v.a = with_exponent(static_cast<std::uint32_t>(ea + f_.bias()), random_sign());
        v.b = with_exponent(clamp_field(eb + f_.bias()), random_sign());
        if (op_ == Op::kFma) v.c = perturb(soft::mul(f_, v.a, v.b) ^ f_.sign_mask());
        if (op_ == Op::kAdd || op_ == Op::kSub) {
          v.a = with_exponent(clamp_field(target + f_.bias()), random_sign());
          v.b = near(v.a, 1);
        }
        break;
      }
      case 5: {  // around 1 and the integers (floor, fract, to_int32, compares)
        v.a = with_exponent(clamp_field(f_.bias() + static_cast<int>(below(34)) - 3), random_sign());
        v.b = below(2) == 0 ? v.a : perturb(v.a);
        break;
      }
      default: {  // one or more edge values among random ones
        if (below(2) == 0) v.a = edge();
        if (below(2) == 0) v.b = edge();
        if (below(2) == 0) v.c = edge();
        break;
      }
    }
    // Half of all square roots of uniform operands would be of negative values, which
    // only give NaN: keep one in eight negative.
    if ((op_ == Op::kSqrt || op_ == Op::kRsqrt) && below(8) != 0) v.a &= ~f_.sign_mask();
    return v;
  }

 private:
  std::uint64_t below(std::uint64_t n) { return rng_() % n; }
  std::uint32_t value() { return static_cast<std::uint32_t>(rng_()) & f_.all_bits(); }
  bool random_sign() { return below(2) == 0; }
  std::uint32_t random_field() { return 1 + static_cast<std::uint32_t>(below(f_.exponent_field_max() - 1)); }
  std::uint32_t clamp_field(int field) {
    return static_cast<std::uint32_t>(std::clamp(field, 1, static_cast<int>(f_.exponent_field_max()) - 1));
  }
  std::uint32_t with_exponent(std::uint32_t field, bool negative) {
    return f_.sign_bit(negative) | (field << f_.fraction_bits) | (value() & f_.fraction_mask());
  }
  // Same sign or not, exponent within `spread` of x's, random fraction.
  std::uint32_t near(std::uint32_t x, int spread) {
    const int delta = static_cast<int>(below(2 * static_cast<std::uint64_t>(spread) + 1)) - spread;
    return with_exponent(clamp_field(static_cast<int>(f_.exponent_field(x)) + delta), random_sign());
  }
  // A few units in the last place away, keeping sign and (mostly) exponent.
  std::uint32_t perturb(std::uint32_t x) {
    if (f_.is_nan(x) || f_.is_inf(x) || f_.is_zero_after_flush(x)) return x;
    const auto delta = static_cast<std::uint32_t>(below(9));
    const std::uint32_t moved = (below(2) == 0 ? x + delta : x - delta) & f_.all_bits();
    return f_.is_negative(moved) == f_.is_negative(x) ? moved : x;
  }
  // Keeps only the top few fraction bits.
  std::uint32_t sparse(std::uint32_t x) {
    const int keep = static_cast<int>(below(static_cast<std::uint64_t>(std::min(f_.fraction_bits, 6)) + 1));
    const std::uint32_t cleared = f_.fraction_mask() >> keep;
    return x & ~cleared;
  }
  std::uint32_t edge() { return edges_[below(edges_.size())]; }

  std::uint32_t from_fp32_input() {
    const auto bits = static_cast<std::uint32_t>(rng_());
    switch (below(3)) {
      case 0: return bits;
      case 1: {  // within the format's exponent range, plus a margin
        const int e = static_cast<int>(below(static_cast<std::uint64_t>(f_.max_exponent() - f_.min_exponent() + 5))) +
                      f_.min_exponent() - 2;
        const int field = std::clamp(e + 127, 0, 255);
        return (bits & 0x807FFFFFu) | (static_cast<std::uint32_t>(field) << 23);
      }
      default: {  // the bits the format drops set to exactly half, or all ones
        const std::uint32_t dropped = (1u << (23 - f_.fraction_bits)) - 1;
        const std::uint32_t tail = below(2) == 0 ? (dropped + 1) >> 1 : dropped;
        const int e = f_.min_exponent() + static_cast<int>(below(4)) - 2 +
                      (below(2) == 0 ? 0 : f_.max_exponent() - f_.min_exponent());
        return (bits & 0x807FFFFFu & ~dropped) | tail | (static_cast<std::uint32_t>(std::clamp(e + 127, 0, 255)) << 23);
      }
    }
  }

  std::uint32_t int32_input() {
    const auto bits = static_cast<std::uint32_t>(rng_());
    // Uniform, or of a random bit length so every binade and its ties are hit.
    if (below(2) == 0) return bits;
    const int length = static_cast<int>(below(32));
    const std::uint32_t magnitude = length == 0 ? 0 : (bits >> (32 - length)) | (1u << (length - 1));
    return below(2) == 0 ? magnitude : 0u - magnitude;
  }

  Op op_;
  Format f_;
  std::mt19937_64 rng_;
  std::vector<std::uint32_t> edges_;
};

}  // namespace rpu::fp
