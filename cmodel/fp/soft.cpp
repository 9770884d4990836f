#include "fp/soft.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace rpu::fp::soft {
namespace {

// GCC and Clang's 128-bit integer; __extension__ keeps -Wpedantic quiet about it.
__extension__ using U128 = unsigned __int128;

enum class Kind { kZero, kFinite, kInf, kNan };

// A decoded operand. For kFinite the value is (-1)^negative * significand *
// 2^exponent, with the significand in [2^M, 2^(M+1)) (hidden bit included).
struct Unpacked {
  Kind kind;
  bool negative;
  int exponent;
  std::uint64_t significand;
};

Unpacked unpack(Format f, std::uint32_t bits) {
  const bool negative = f.is_negative(bits);
  const std::uint32_t field = f.exponent_field(bits);
  const std::uint32_t fraction = bits & f.fraction_mask();
  // Exponent field 0 is zero or subnormal; both read as a signed zero (DAZ).
  if (field == 0) return {Kind::kZero, negative, 0, 0};
  if (field == f.exponent_field_max()) return {fraction != 0 ? Kind::kNan : Kind::kInf, negative, 0, 0};
  return {Kind::kFinite, negative, static_cast<int>(field) - f.bias() - f.fraction_bits,
          fraction | (std::uint64_t{1} << f.fraction_bits)};
}

int msb(U128 x) {
  const auto high = static_cast<std::uint64_t>(x >> 64);
  if (high != 0) return 127 - __builtin_clzll(high);
  return 63 - __builtin_clzll(static_cast<std::uint64_t>(x));
}

// Shifts right, OR-ing every bit shifted out into bit 0 (the sticky bit).
U128 shift_right_sticky(U128 x, int shift) {
  if (shift <= 0) return x;
  if (shift >= 128) return x != 0 ? 1 : 0;
  const U128 lost = x & ((U128{1} << shift) - 1);
  return (x >> shift) | (lost != 0 ? 1 : 0);
}

// The one rounding step of every operation: rounds significand * 2^exponent (> 0)
// to M+1 significant bits, nearest-even (IEEE 754-2019 §4.3.1), with an unbounded
// exponent; then overflows to infinity (§7.4) or, if the rounded value is below the
// smallest normal, flushes to zero of the same sign (tininess after rounding, §7.5,
// with the flush in place of a subnormal result).
//
// Bit 0 of `significand` may be a sticky bit standing for nonzero bits below it.
// That keeps the rounding exact as long as the significand then has at least M+3
// bits: the sticky bit sits below the guard bit, and neither the true nor the
// sticky value can be a rounding boundary.
std::uint32_t round_pack(Format f, bool negative, int exponent, U128 significand) {
  const int m = f.fraction_bits;
  const int top = msb(significand);
  const int shift = top - m;
  std::uint64_t kept = 0;
  if (shift > 0) {
    const U128 rest = significand & ((U128{1} << shift) - 1);
    const U128 half = U128{1} << (shift - 1);
    kept = static_cast<std::uint64_t>(significand >> shift);
    if (rest > half || (rest == half && (kept & 1) != 0)) ++kept;
  } else {
    kept = static_cast<std::uint64_t>(significand) << -shift;
  }
  int leading = exponent + top;  // exponent of the leading bit
  if ((kept >> (m + 1)) != 0) {  // rounding carried into a new binade
    kept >>= 1;
    ++leading;
  }
  if (leading > f.max_exponent()) return f.infinity(negative);
  if (leading < f.min_exponent()) return f.zero(negative);
  return f.sign_bit(negative) | (static_cast<std::uint32_t>(leading + f.bias()) << m) |
         (static_cast<std::uint32_t>(kept) & f.fraction_mask());
}

std::uint32_t pack(Format f, const Unpacked& x) { return round_pack(f, x.negative, x.exponent, x.significand); }

// Sum of two nonzero finite values a_sig * 2^a_exp and b_sig * 2^b_exp, each given
// exactly, rounded once. Both are first normalised to a leading bit at 125 (two bits
// of headroom for the carry); the smaller is then aligned with a sticky bit. With
// at most 48 significant bits per operand (a product) the alignment is exact for gaps up to 76
// bits, and beyond that the larger operand keeps over 70 bits above the sticky bit.
std::uint32_t add_exact(Format f, bool a_negative, int a_exp, U128 a_sig, bool b_negative, int b_exp,
                        U128 b_sig) {
  const int a_shift = 125 - msb(a_sig);
  a_sig <<= a_shift;
  a_exp -= a_shift;
  const int b_shift = 125 - msb(b_sig);
  b_sig <<= b_shift;
  b_exp -= b_shift;
  if (a_exp < b_exp || (a_exp == b_exp && a_sig < b_sig)) {
    std::swap(a_negative, b_negative);
    std::swap(a_exp, b_exp);
    std::swap(a_sig, b_sig);
  }
  const U128 aligned = shift_right_sticky(b_sig, a_exp - b_exp);
  const U128 sum = a_negative == b_negative ? a_sig + aligned : a_sig - aligned;
  // IEEE 754-2019 §6.3: an exact zero sum of operands of opposite sign is +0 in
  // roundTiesToEven.
  if (sum == 0) return f.zero(false);
  return round_pack(f, a_negative, a_exp, sum);
}

// Sign of an exact zero sum x + y of two zeros (IEEE 754-2019 §6.3).
std::uint32_t zero_sum(Format f, bool x_negative, bool y_negative) { return f.zero(x_negative && y_negative); }

std::uint64_t isqrt(std::uint64_t n) {
  // The host square root only gives a starting point; the integer corrections make
  // the result exactly floor(sqrt(n)).
  auto root = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
  while (U128{root} * root > n) --root;
  while (U128{root + 1} * (root + 1) <= n) ++root;
  return root;
}

// Orders flushed non-NaN values; zeros of either sign share the key 0 (IEEE 754-2019
// §5.11: +0 == -0).
std::int64_t compare_key(Format f, std::uint32_t flushed) {
  const auto magnitude = static_cast<std::int64_t>(flushed & ~f.sign_mask());
  return f.is_negative(flushed) ? -magnitude : magnitude;
}

// Like compare_key, but -0 sorts below +0 as min and max require.
std::int64_t min_max_key(Format f, std::uint32_t flushed) {
  const auto magnitude = static_cast<std::int64_t>(flushed & ~f.sign_mask());
  return f.is_negative(flushed) ? -magnitude - 1 : magnitude;
}

}  // namespace

std::uint32_t flush(Format f, std::uint32_t a) {
  if (f.is_nan(a)) return f.canonical_nan();
  if (f.is_zero_after_flush(a)) return f.zero(f.is_negative(a));
  return a;
}

std::uint32_t add(Format f, std::uint32_t a, std::uint32_t b) {
  const Unpacked x = unpack(f, a);
  const Unpacked y = unpack(f, b);
  if (x.kind == Kind::kNan || y.kind == Kind::kNan) return f.canonical_nan();
  if (x.kind == Kind::kInf) {
    // §7.2(b): inf - inf is invalid.
    if (y.kind == Kind::kInf && x.negative != y.negative) return f.canonical_nan();
    return f.infinity(x.negative);
  }
  if (y.kind == Kind::kInf) return f.infinity(y.negative);
  if (x.kind == Kind::kZero && y.kind == Kind::kZero) return zero_sum(f, x.negative, y.negative);
  if (x.kind == Kind::kZero) return pack(f, y);
  if (y.kind == Kind::kZero) return pack(f, x);
  return add_exact(f, x.negative, x.exponent, x.significand, y.negative, y.exponent, y.significand);
}

std::uint32_t sub(Format f, std::uint32_t a, std::uint32_t b) { return add(f, a, b ^ f.sign_mask()); }

std::uint32_t mul(Format f, std::uint32_t a, std::uint32_t b) {
  const Unpacked x = unpack(f, a);
  const Unpacked y = unpack(f, b);
  const bool negative = x.negative != y.negative;
  if (x.kind == Kind::kNan || y.kind == Kind::kNan) return f.canonical_nan();
  if (x.kind == Kind::kInf || y.kind == Kind::kInf) {
    // §7.2(b): 0 * inf is invalid.
    if (x.kind == Kind::kZero || y.kind == Kind::kZero) return f.canonical_nan();
    return f.infinity(negative);
  }
  if (x.kind == Kind::kZero || y.kind == Kind::kZero) return f.zero(negative);
  return round_pack(f, negative, x.exponent + y.exponent, U128{x.significand} * y.significand);
}

std::uint32_t fma(Format f, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const Unpacked x = unpack(f, a);
  const Unpacked y = unpack(f, b);
  const Unpacked z = unpack(f, c);
  const bool product_negative = x.negative != y.negative;
  if (x.kind == Kind::kNan || y.kind == Kind::kNan || z.kind == Kind::kNan) return f.canonical_nan();
  if (x.kind == Kind::kInf || y.kind == Kind::kInf) {
    // §7.2(c): fma(0, inf, c) is invalid whatever c is (c is not NaN here).
    if (x.kind == Kind::kZero || y.kind == Kind::kZero) return f.canonical_nan();
    if (z.kind == Kind::kInf && z.negative != product_negative) return f.canonical_nan();
    return f.infinity(product_negative);
  }
  if (z.kind == Kind::kInf) return f.infinity(z.negative);
  if (x.kind == Kind::kZero || y.kind == Kind::kZero) {
    if (z.kind == Kind::kZero) return zero_sum(f, product_negative, z.negative);
    return pack(f, z);
  }
  const int product_exp = x.exponent + y.exponent;
  const U128 product_sig = U128{x.significand} * y.significand;
  if (z.kind == Kind::kZero) return round_pack(f, product_negative, product_exp, product_sig);
  return add_exact(f, product_negative, product_exp, product_sig, z.negative, z.exponent, z.significand);
}

std::uint32_t div(Format f, std::uint32_t a, std::uint32_t b) {
  const Unpacked x = unpack(f, a);
  const Unpacked y = unpack(f, b);
  const bool negative = x.negative != y.negative;
  if (x.kind == Kind::kNan || y.kind == Kind::kNan) return f.canonical_nan();
  if (x.kind == Kind::kInf) return y.kind == Kind::kInf ? f.canonical_nan() : f.infinity(negative);
  if (y.kind == Kind::kInf) return f.zero(negative);
  if (y.kind == Kind::kZero) {
    // §7.2(d) 0/0 is invalid; §7.3 x/0 is an exact infinity.
    return x.kind == Kind::kZero ? f.canonical_nan() : f.infinity(negative);
  }
  if (x.kind == Kind::kZero) return f.zero(negative);
  // The dividend shifted up by 40 gives a quotient of at least 2^39, far more than
  // the M+3 bits the sticky rounding needs; the remainder becomes the sticky bit.
  constexpr int kShift = 40;
  const std::uint64_t dividend = x.significand << kShift;
  const std::uint64_t quotient = dividend / y.significand;
  const bool inexact = dividend % y.significand != 0;
  return round_pack(f, negative, x.exponent - y.exponent - kShift, U128{quotient | (inexact ? 1u : 0u)});
}

std::uint32_t rcp(Format f, std::uint32_t a) { return div(f, f.one(false), a); }

std::uint32_t sqrt(Format f, std::uint32_t a) {
  const Unpacked x = unpack(f, a);
  if (x.kind == Kind::kNan) return f.canonical_nan();
  // §6.3: sqrt(-0) = -0; §7.2(g): sqrt of a negative nonzero value is invalid.
  if (x.kind == Kind::kZero) return f.zero(x.negative);
  if (x.negative) return f.canonical_nan();
  if (x.kind == Kind::kInf) return f.infinity(false);
  // Scale the significand to [2^61, 2^63) with an even exponent left over, so the
  // integer root has at least 30 bits.
  int shift = 62 - f.fraction_bits;
  if (((x.exponent - shift) & 1) != 0) --shift;
  const std::uint64_t scaled = x.significand << shift;
  const std::uint64_t root = isqrt(scaled);
  const bool inexact = root * root != scaled;
  return round_pack(f, false, (x.exponent - shift) / 2, U128{root | (inexact ? 1u : 0u)});
}

std::uint32_t rsqrt(Format f, std::uint32_t a) { return rcp(f, sqrt(f, a)); }

std::uint32_t min(Format f, std::uint32_t a, std::uint32_t b) {
  a = flush(f, a);
  b = flush(f, b);
  if (f.is_nan(a) || f.is_nan(b)) return f.canonical_nan();
  return min_max_key(f, a) <= min_max_key(f, b) ? a : b;
}

std::uint32_t max(Format f, std::uint32_t a, std::uint32_t b) {
  a = flush(f, a);
  b = flush(f, b);
  if (f.is_nan(a) || f.is_nan(b)) return f.canonical_nan();
  return min_max_key(f, a) >= min_max_key(f, b) ? a : b;
}

std::uint32_t floor(Format f, std::uint32_t a) {
  const Unpacked x = unpack(f, a);
  if (x.kind == Kind::kNan) return f.canonical_nan();
  if (x.kind != Kind::kFinite) return flush(f, a);
  if (x.exponent >= 0) return a;  // no fraction bits below the binary point
  const int fraction_bits = -x.exponent;
  // |a| < 1: §5.9 roundToIntegralTowardNegative gives +0 or -1.
  if (fraction_bits > f.fraction_bits) return x.negative ? f.one(true) : f.zero(false);
  std::uint64_t integer = x.significand >> fraction_bits;
  const bool has_fraction = (x.significand & ((std::uint64_t{1} << fraction_bits) - 1)) != 0;
  if (x.negative && has_fraction) ++integer;
  return round_pack(f, x.negative, 0, U128{integer});
}

std::uint32_t fract(Format f, std::uint32_t a) { return sub(f, a, floor(f, a)); }

bool eq(Format f, std::uint32_t a, std::uint32_t b) {
  a = flush(f, a);
  b = flush(f, b);
  if (f.is_nan(a) || f.is_nan(b)) return false;
  return compare_key(f, a) == compare_key(f, b);
}

bool ne(Format f, std::uint32_t a, std::uint32_t b) { return !eq(f, a, b); }

bool lt(Format f, std::uint32_t a, std::uint32_t b) {
  a = flush(f, a);
  b = flush(f, b);
  if (f.is_nan(a) || f.is_nan(b)) return false;
  return compare_key(f, a) < compare_key(f, b);
}

bool le(Format f, std::uint32_t a, std::uint32_t b) {
  a = flush(f, a);
  b = flush(f, b);
  if (f.is_nan(a) || f.is_nan(b)) return false;
  return compare_key(f, a) <= compare_key(f, b);
}

bool gt(Format f, std::uint32_t a, std::uint32_t b) { return lt(f, b, a); }
bool ge(Format f, std::uint32_t a, std::uint32_t b) { return le(f, b, a); }

std::uint32_t from_fp32(Format f, std::uint32_t fp32_bits) {
  const Unpacked x = unpack(kFp32, fp32_bits);
  switch (x.kind) {
    case Kind::kNan: return f.canonical_nan();
    case Kind::kInf: return f.infinity(x.negative);
    case Kind::kZero: return f.zero(x.negative);
    case Kind::kFinite: break;
  }
  return pack(f, x);
}

std::uint32_t to_fp32(Format f, std::uint32_t a) {
  const Unpacked x = unpack(f, a);
  switch (x.kind) {
    case Kind::kNan: return kFp32.canonical_nan();
    case Kind::kInf: return kFp32.infinity(x.negative);
    case Kind::kZero: return kFp32.zero(x.negative);
    case Kind::kFinite: break;
  }
  return pack(kFp32, x);  // exact: fp32 has at least the format's range and precision
}

std::uint32_t from_int32(Format f, std::int32_t value) {
  if (value == 0) return f.zero(false);
  const bool negative = value < 0;
  const auto magnitude = static_cast<std::uint64_t>(negative ? -static_cast<std::int64_t>(value) : value);
  return round_pack(f, negative, 0, U128{magnitude});
}

std::int32_t to_int32(Format f, std::uint32_t a) {
  const Unpacked x = unpack(f, a);
  constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
  constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();
  switch (x.kind) {
    case Kind::kNan: return 0;
    case Kind::kInf: return x.negative ? kMin : kMax;
    case Kind::kZero: return 0;
    case Kind::kFinite: break;
  }
  // |a| >= 2^31 saturates (for -2^31 the saturated value is the exact one).
  if (x.exponent + f.fraction_bits >= 31) return x.negative ? kMin : kMax;
  const std::uint64_t magnitude = x.exponent >= 0 ? x.significand << x.exponent
                                  : x.exponent <= -64 ? 0
                                                      : x.significand >> -x.exponent;
  const auto value = static_cast<std::int64_t>(magnitude);
  return static_cast<std::int32_t>(x.negative ? -value : value);
}

}  // namespace rpu::fp::soft
