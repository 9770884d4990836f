#pragma once

#include <cstdint>

#include "fp/format.hpp"

// Arithmetic in any Format by integer computation: every operation is computed
// exactly (or with a sticky bit that keeps the rounding decision exact) and rounded
// once by one shared routine. The contract is docs/numbers.md: round to nearest
// even, subnormal inputs read as signed zero, tiny results (after rounding) flush to
// signed zero, overflow to infinity, one canonical NaN. Operands are bit patterns of
// width f.width(), right-aligned, with the bits above zero.
namespace rpu::fp::soft {

std::uint32_t add(Format f, std::uint32_t a, std::uint32_t b);
std::uint32_t sub(Format f, std::uint32_t a, std::uint32_t b);
std::uint32_t mul(Format f, std::uint32_t a, std::uint32_t b);
// a * b + c with one rounding (IEEE 754-2019 §5.4.1 fusedMultiplyAdd).
std::uint32_t fma(Format f, std::uint32_t a, std::uint32_t b, std::uint32_t c);
std::uint32_t div(Format f, std::uint32_t a, std::uint32_t b);
// div(1, a): correctly rounded.
std::uint32_t rcp(Format f, std::uint32_t a);
std::uint32_t sqrt(Format f, std::uint32_t a);
// rcp(sqrt(a)): two roundings, so it matches 1.0f / sqrtf(a) on the fp32 path.
std::uint32_t rsqrt(Format f, std::uint32_t a);
// NaN in either input gives the canonical NaN; -0 < +0.
std::uint32_t min(Format f, std::uint32_t a, std::uint32_t b);
std::uint32_t max(Format f, std::uint32_t a, std::uint32_t b);
// Rounds toward -inf to an integer; exact.
std::uint32_t floor(Format f, std::uint32_t a);
// a - floor(a), rounded once; can round to 1.0 for tiny negative a.
std::uint32_t fract(Format f, std::uint32_t a);

// IEEE 754-2019 §5.11 quiet comparisons: any NaN makes all false except ne.
bool eq(Format f, std::uint32_t a, std::uint32_t b);
bool ne(Format f, std::uint32_t a, std::uint32_t b);
bool lt(Format f, std::uint32_t a, std::uint32_t b);
bool le(Format f, std::uint32_t a, std::uint32_t b);
bool gt(Format f, std::uint32_t a, std::uint32_t b);
bool ge(Format f, std::uint32_t a, std::uint32_t b);

// fp32 bits into the format: rounded, flushed, overflow to inf, NaN canonical.
std::uint32_t from_fp32(Format f, std::uint32_t fp32_bits);
// The format into fp32 bits: exact (after the input flush; NaN canonical).
std::uint32_t to_fp32(Format f, std::uint32_t a);
std::uint32_t from_int32(Format f, std::int32_t value);
// Truncates toward zero, saturates to INT32_MIN / INT32_MAX, NaN gives 0.
std::int32_t to_int32(Format f, std::uint32_t a);

// The input flush (DAZ): a subnormal becomes zero of its sign; a NaN becomes the
// canonical NaN; everything else is returned unchanged.
std::uint32_t flush(Format f, std::uint32_t a);

}  // namespace rpu::fp::soft
