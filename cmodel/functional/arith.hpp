#pragma once

#include <bit>
#include <cstdint>

#include "fp/fast32.hpp"
#include "fp/format.hpp"
#include "fp/soft.hpp"

namespace rpu::functional {

// The arithmetic the shader cores and the trace units compute with, as two
// interchangeable policies with the same meaning (docs/numbers.md): SoftArith for any
// format, Fast32Arith for fp32 on host float. Both give the same bits for every value
// stored (store()); a NaN Value may differ in sign and payload between them (host
// float makes its own NaNs), which store() and every operation treat as the one
// canonical NaN.
//
// Value; load(fp32 bits) rounds into the format; store(v) widens to fp32 bits; the
// operations of docs/numbers.md; neg and abs; from_int, to_int; sign(v) = sign bit;
// zero(), one().
//
// neg and abs are the sign operations of the source modifiers (docs/shader-core.md
// "Values"): exact, and a NaN passes through both unchanged, bit for bit.

struct SoftArith {
  using Value = std::uint32_t;
  fp::Format format;

  Value load(std::uint32_t fp32_bits) const { return fp::soft::from_fp32(format, fp32_bits); }
  std::uint32_t store(Value a) const { return fp::soft::to_fp32(format, a); }
  Value add(Value a, Value b) const { return fp::soft::add(format, a, b); }
  Value sub(Value a, Value b) const { return fp::soft::sub(format, a, b); }
  Value mul(Value a, Value b) const { return fp::soft::mul(format, a, b); }
  Value fma(Value a, Value b, Value c) const { return fp::soft::fma(format, a, b, c); }
  Value div(Value a, Value b) const { return fp::soft::div(format, a, b); }
  Value rcp(Value a) const { return fp::soft::rcp(format, a); }
  Value sqrt(Value a) const { return fp::soft::sqrt(format, a); }
  Value rsqrt(Value a) const { return fp::soft::rsqrt(format, a); }
  Value min(Value a, Value b) const { return fp::soft::min(format, a, b); }
  Value max(Value a, Value b) const { return fp::soft::max(format, a, b); }
  Value floor(Value a) const { return fp::soft::floor(format, a); }
  Value fract(Value a) const { return fp::soft::fract(format, a); }
  Value neg(Value a) const { return format.is_nan(a) ? a : a ^ format.sign_mask(); }
  Value abs(Value a) const { return format.is_nan(a) ? a : a & ~format.sign_mask(); }
  bool eq(Value a, Value b) const { return fp::soft::eq(format, a, b); }
  bool ne(Value a, Value b) const { return fp::soft::ne(format, a, b); }
  bool lt(Value a, Value b) const { return fp::soft::lt(format, a, b); }
  bool le(Value a, Value b) const { return fp::soft::le(format, a, b); }
  bool gt(Value a, Value b) const { return fp::soft::gt(format, a, b); }
  Value from_int(std::int32_t v) const { return fp::soft::from_int32(format, v); }
  std::int32_t to_int(Value a) const { return fp::soft::to_int32(format, a); }
  bool sign(Value a) const { return (a & format.sign_mask()) != 0; }
  Value zero() const { return format.zero(false); }
  Value one() const { return format.one(false); }
};

// fp32 on host float. Correct only while fp::fast32::FlushScope holds MXCSR.FTZ|DAZ on
// the calling thread and the build does not contract a*b+c (-ffp-contract=off). A
// Value is never subnormal (load flushes, FTZ flushes every result), so the plain
// float operations below equal fp::fast32's; the others are fp::fast32's own.
struct Fast32Arith {
  using Value = float;

  Value load(std::uint32_t fp32_bits) const {
    // Flush subnormal inputs explicitly rather than trusting DAZ for every later use.
    if ((fp32_bits & 0x7f800000u) == 0) fp32_bits &= 0x80000000u;
    return std::bit_cast<float>(fp32_bits);
  }
  std::uint32_t store(Value a) const { return a != a ? fp::kFp32.canonical_nan() : bits(a); }
  Value add(Value a, Value b) const { return a + b; }
  Value sub(Value a, Value b) const { return a - b; }
  Value mul(Value a, Value b) const { return a * b; }
  Value fma(Value a, Value b, Value c) const { return value(fp::fast32::fma(bits(a), bits(b), bits(c))); }
  Value div(Value a, Value b) const { return a / b; }
  Value rcp(Value a) const { return 1.0f / a; }
  Value sqrt(Value a) const { return value(fp::fast32::sqrt(bits(a))); }
  Value rsqrt(Value a) const { return value(fp::fast32::rsqrt(bits(a))); }
  Value min(Value a, Value b) const { return value(fp::fast32::min(bits(a), bits(b))); }
  Value max(Value a, Value b) const { return value(fp::fast32::max(bits(a), bits(b))); }
  Value floor(Value a) const { return value(fp::fast32::floor(bits(a))); }
  Value fract(Value a) const { return value(fp::fast32::fract(bits(a))); }
  // Not -a: host negation flips a NaN's sign bit.
  Value neg(Value a) const { return a != a ? a : value(bits(a) ^ 0x80000000u); }
  Value abs(Value a) const { return a != a ? a : value(bits(a) & 0x7fffffffu); }
  bool eq(Value a, Value b) const { return a == b; }
  bool ne(Value a, Value b) const { return a != b; }
  bool lt(Value a, Value b) const { return a < b; }
  bool le(Value a, Value b) const { return a <= b; }
  bool gt(Value a, Value b) const { return a > b; }
  Value from_int(std::int32_t v) const { return value(fp::fast32::from_int32(v)); }
  std::int32_t to_int(Value a) const { return fp::fast32::to_int32(bits(a)); }
  bool sign(Value a) const { return (bits(a) >> 31) != 0; }
  Value zero() const { return 0.0f; }
  Value one() const { return 1.0f; }

 private:
  static std::uint32_t bits(Value a) { return std::bit_cast<std::uint32_t>(a); }
  static Value value(std::uint32_t b) { return std::bit_cast<float>(b); }
};

}  // namespace rpu::functional
