#pragma once

#include <bit>
#include <cstdint>

#include "fp/format.hpp"
#include "fp/soft.hpp"

namespace rpu::functional {

// The arithmetic the trace units compute with, as two interchangeable policies with the
// same meaning (docs/numbers.md): SoftArith for any format, Fast32Arith for fp32 on host
// float. Both give the same bits for every value the units output; they may differ
// only in the payload of NaNs, which the units never output (a NaN fails every test
// that would let it through, docs/traversal.md).
//
// Policy interface: Value; load(fp32 bits) rounds into the format; store(v) widens to
// fp32 bits; add sub mul div neg abs rcp; lt le gt eq; sign(v) = sign bit; zero(), one().

struct SoftArith {
  using Value = std::uint32_t;
  fp::Format format;

  Value load(std::uint32_t fp32_bits) const { return fp::soft::from_fp32(format, fp32_bits); }
  std::uint32_t store(Value a) const { return fp::soft::to_fp32(format, a); }
  Value add(Value a, Value b) const { return fp::soft::add(format, a, b); }
  Value sub(Value a, Value b) const { return fp::soft::sub(format, a, b); }
  Value mul(Value a, Value b) const { return fp::soft::mul(format, a, b); }
  Value div(Value a, Value b) const { return fp::soft::div(format, a, b); }
  Value rcp(Value a) const { return fp::soft::rcp(format, a); }
  // Sign flips are exact; a NaN stays the canonical NaN.
  Value neg(Value a) const { return format.is_nan(a) ? a : a ^ format.sign_mask(); }
  Value abs(Value a) const { return format.is_nan(a) ? a : a & ~format.sign_mask(); }
  bool lt(Value a, Value b) const { return fp::soft::lt(format, a, b); }
  bool le(Value a, Value b) const { return fp::soft::le(format, a, b); }
  bool gt(Value a, Value b) const { return fp::soft::gt(format, a, b); }
  bool eq(Value a, Value b) const { return fp::soft::eq(format, a, b); }
  bool sign(Value a) const { return (a & format.sign_mask()) != 0; }
  Value zero() const { return format.zero(false); }
  Value one() const { return format.one(false); }
};

// fp32 on host float. Correct only while fp::fast32::FlushScope holds MXCSR.FTZ|DAZ on
// the calling thread and the build does not contract a*b+c (-ffp-contract=off).
struct Fast32Arith {
  using Value = float;

  Value load(std::uint32_t fp32_bits) const {
    // Flush subnormal inputs explicitly rather than trusting DAZ for every later use.
    if ((fp32_bits & 0x7f800000u) == 0) fp32_bits &= 0x80000000u;
    return std::bit_cast<float>(fp32_bits);
  }
  std::uint32_t store(Value a) const {
    return a != a ? fp::kFp32.canonical_nan() : std::bit_cast<std::uint32_t>(a);
  }
  Value add(Value a, Value b) const { return a + b; }
  Value sub(Value a, Value b) const { return a - b; }
  Value mul(Value a, Value b) const { return a * b; }
  Value div(Value a, Value b) const { return a / b; }
  Value rcp(Value a) const { return 1.0f / a; }
  Value neg(Value a) const { return -a; }
  Value abs(Value a) const { return std::bit_cast<float>(std::bit_cast<std::uint32_t>(a) & 0x7fffffffu); }
  bool lt(Value a, Value b) const { return a < b; }
  bool le(Value a, Value b) const { return a <= b; }
  bool gt(Value a, Value b) const { return a > b; }
  bool eq(Value a, Value b) const { return a == b; }
  bool sign(Value a) const { return (std::bit_cast<std::uint32_t>(a) >> 31) != 0; }
  Value zero() const { return 0.0f; }
  Value one() const { return 1.0f; }
};

}  // namespace rpu::functional
