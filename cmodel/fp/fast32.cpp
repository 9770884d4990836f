#include "fp/fast32.hpp"

#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

#include "fp/format.hpp"

#if !defined(__SSE2__)
#error "the fp32 fast path needs x86 SSE (MXCSR flush-to-zero and denormals-are-zero)"
#endif
#include <xmmintrin.h>

namespace rpu::fp::fast32 {
namespace {

// Intel SDM vol. 1 §10.2.3: MXCSR bit 15 is flush-to-zero, bit 6 denormals-are-zero.
constexpr unsigned int kFlushBits = 0x8040;

float to_float(std::uint32_t bits) { return std::bit_cast<float>(bits); }

// x86 produces the "real indefinite" 0xFFC00000 or propagates an input payload;
// the contract has one canonical NaN.
std::uint32_t result(float value) {
  return std::isnan(value) ? kFp32.canonical_nan() : std::bit_cast<std::uint32_t>(value);
}

// DAZ by bits: for the library calls (fmaf, floorf) that may run in integer or
// non-SSE code and so not see MXCSR.DAZ, and for the ops that return or compare an
// input (min, max, compares, to_int32), which then do not depend on MXCSR at all.
float flushed(std::uint32_t a) { return to_float(flush(a)); }

}  // namespace

FlushScope::FlushScope() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushBits); }
FlushScope::~FlushScope() { _mm_setcsr(saved_); }

bool flush_mode_active() { return (_mm_getcsr() & kFlushBits) == kFlushBits; }

std::uint32_t flush(std::uint32_t a) {
  if (kFp32.is_nan(a)) return kFp32.canonical_nan();
  if (kFp32.is_zero_after_flush(a)) return a & kFp32.sign_mask();
  return a;
}

std::uint32_t add(std::uint32_t a, std::uint32_t b) {
  assert(flush_mode_active());
  return result(to_float(a) + to_float(b));
}

std::uint32_t sub(std::uint32_t a, std::uint32_t b) {
  assert(flush_mode_active());
  return result(to_float(a) - to_float(b));
}

std::uint32_t mul(std::uint32_t a, std::uint32_t b) {
  assert(flush_mode_active());
  return result(to_float(a) * to_float(b));
}

std::uint32_t fma(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  assert(flush_mode_active());
  return result(std::fma(flushed(a), flushed(b), flushed(c)));
}

std::uint32_t div(std::uint32_t a, std::uint32_t b) {
  assert(flush_mode_active());
  return result(to_float(a) / to_float(b));
}

std::uint32_t rcp(std::uint32_t a) {
  assert(flush_mode_active());
  return result(1.0f / to_float(a));
}

std::uint32_t sqrt(std::uint32_t a) {
  assert(flush_mode_active());
  return result(std::sqrt(to_float(a)));
}

std::uint32_t rsqrt(std::uint32_t a) {
  assert(flush_mode_active());
  // Two roundings, as the contract defines rsqrt.
  const float root = std::sqrt(to_float(a));
  return result(1.0f / root);
}

std::uint32_t min(std::uint32_t a, std::uint32_t b) {
  const float x = flushed(a);
  const float y = flushed(b);
  if (std::isnan(x) || std::isnan(y)) return kFp32.canonical_nan();
  // -0 < +0 for min and max (docs/numbers.md).
  if (x == y) return std::signbit(x) ? flush(a) : flush(b);
  return x < y ? flush(a) : flush(b);
}

std::uint32_t max(std::uint32_t a, std::uint32_t b) {
  const float x = flushed(a);
  const float y = flushed(b);
  if (std::isnan(x) || std::isnan(y)) return kFp32.canonical_nan();
  if (x == y) return std::signbit(x) ? flush(b) : flush(a);
  return x > y ? flush(a) : flush(b);
}

std::uint32_t floor(std::uint32_t a) { return result(std::floor(flushed(a))); }

std::uint32_t fract(std::uint32_t a) {
  assert(flush_mode_active());
  const float x = flushed(a);
  return result(x - std::floor(x));
}

// Comparisons on explicitly flushed values: ordinary C++ comparisons are IEEE 754
// quiet predicates (false on NaN, +0 == -0).
bool eq(std::uint32_t a, std::uint32_t b) { return flushed(a) == flushed(b); }
bool ne(std::uint32_t a, std::uint32_t b) { return !eq(a, b); }
bool lt(std::uint32_t a, std::uint32_t b) { return flushed(a) < flushed(b); }
bool le(std::uint32_t a, std::uint32_t b) { return flushed(a) <= flushed(b); }
bool gt(std::uint32_t a, std::uint32_t b) { return flushed(a) > flushed(b); }
bool ge(std::uint32_t a, std::uint32_t b) { return flushed(a) >= flushed(b); }

std::uint32_t from_fp32(std::uint32_t fp32_bits) { return flush(fp32_bits); }
std::uint32_t to_fp32(std::uint32_t a) { return flush(a); }

std::uint32_t from_int32(std::int32_t value) { return result(static_cast<float>(value)); }

std::int32_t to_int32(std::uint32_t a) {
  const float x = flushed(a);
  if (std::isnan(x)) return 0;
  // 2^31 is exact in float; converting anything at or beyond it is undefined in C++.
  constexpr float kTwo31 = 2147483648.0f;
  if (x >= kTwo31) return std::numeric_limits<std::int32_t>::max();
  if (x <= -kTwo31) return std::numeric_limits<std::int32_t>::min();
  return static_cast<std::int32_t>(x);
}

}  // namespace rpu::fp::fast32
