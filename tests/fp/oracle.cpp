#include "oracle.hpp"

#include <mpfr.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rpu::fp::oracle {
namespace {

constexpr std::array kOps{
    OpInfo{Op::kAdd, "add", 2, Result::kValue},         OpInfo{Op::kSub, "sub", 2, Result::kValue},
    OpInfo{Op::kMul, "mul", 2, Result::kValue},         OpInfo{Op::kFma, "fma", 3, Result::kValue},
    OpInfo{Op::kDiv, "div", 2, Result::kValue},         OpInfo{Op::kRcp, "rcp", 1, Result::kValue},
    OpInfo{Op::kSqrt, "sqrt", 1, Result::kValue},       OpInfo{Op::kRsqrt, "rsqrt", 1, Result::kValue},
    OpInfo{Op::kMin, "min", 2, Result::kValue},         OpInfo{Op::kMax, "max", 2, Result::kValue},
    OpInfo{Op::kFloor, "floor", 1, Result::kValue},     OpInfo{Op::kFract, "fract", 1, Result::kValue},
    OpInfo{Op::kEq, "eq", 2, Result::kBool},            OpInfo{Op::kNe, "ne", 2, Result::kBool},
    OpInfo{Op::kLt, "lt", 2, Result::kBool},            OpInfo{Op::kLe, "le", 2, Result::kBool},
    OpInfo{Op::kGt, "gt", 2, Result::kBool},            OpInfo{Op::kGe, "ge", 2, Result::kBool},
    OpInfo{Op::kFromFp32, "from_fp32", 1, Result::kValue}, OpInfo{Op::kToFp32, "to_fp32", 1, Result::kValue},
    OpInfo{Op::kFromInt32, "from_int32", 1, Result::kValue}, OpInfo{Op::kToInt32, "to_int32", 1, Result::kInt32},
};

// Enough for every exact input (24 bits) and every floor (an integer of at most 24
// bits); results are computed at M+1 bits.
constexpr mpfr_prec_t kWide = 64;

// One MPFR variable, reused across calls (init and clear dominate otherwise).
class Real {
 public:
  Real() { mpfr_init2(value_, kWide); }
  ~Real() { mpfr_clear(value_); }
  Real(const Real&) = delete;
  Real& operator=(const Real&) = delete;
  mpfr_ptr get() { return value_; }
  mpfr_ptr at(mpfr_prec_t precision) {
    mpfr_set_prec(value_, precision);
    return value_;
  }

 private:
  mpfr_t value_;
};

struct Scratch {
  Scratch() {
    // The widest exponent range MPFR has: nothing any format can produce over- or
    // underflows in MPFR itself, so every result is rounded with unbounded exponent.
    mpfr_set_emin(mpfr_get_emin_min());
    mpfr_set_emax(mpfr_get_emax_max());
  }
  Real x, y, z, r, t;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// Input flush (DAZ), then the exact value.
void decode(Format f, std::uint32_t bits, mpfr_ptr out) {
  mpfr_set_prec(out, kWide);
  const bool negative = ((bits >> (f.width() - 1)) & 1) != 0;
  const std::uint32_t field = (bits >> f.fraction_bits) & ((1u << f.exponent_bits) - 1);
  const std::uint32_t fraction = bits & ((1u << f.fraction_bits) - 1);
  if (field == 0) {
    mpfr_set_zero(out, negative ? -1 : 1);
  } else if (field == (1u << f.exponent_bits) - 1) {
    if (fraction != 0) {
      mpfr_set_nan(out);
    } else {
      mpfr_set_inf(out, negative ? -1 : 1);
    }
  } else {
    const int bias = (1 << (f.exponent_bits - 1)) - 1;
    mpfr_set_ui_2exp(out, fraction | (1u << f.fraction_bits),
                     static_cast<int>(field) - bias - f.fraction_bits, MPFR_RNDN);
    if (negative) mpfr_neg(out, out, MPFR_RNDN);
  }
}

// Rounds to M+1 bits (exact if the value already fits), then applies the format's
// range: above the largest finite is infinity, below the smallest normal is a zero
// of the value's sign.
std::uint32_t encode(Format f, mpfr_srcptr value) {
  const int m = f.fraction_bits;
  const int bias = (1 << (f.exponent_bits - 1)) - 1;
  const std::uint32_t sign = mpfr_signbit(value) ? 1u << (f.width() - 1) : 0;
  const std::uint32_t exponent_ones = ((1u << f.exponent_bits) - 1) << m;
  if (mpfr_nan_p(value)) return exponent_ones | (1u << (m - 1));
  if (mpfr_inf_p(value)) return sign | exponent_ones;
  if (mpfr_zero_p(value)) return sign;
  mpfr_ptr t = scratch().t.at(m + 1);
  mpfr_set(t, value, MPFR_RNDN);
  const long leading = mpfr_get_exp(t) - 1;  // MPFR's significand is in [1/2, 1)
  if (leading > bias) return sign | exponent_ones;
  if (leading < 1 - bias) return sign;
  mpfr_abs(t, t, MPFR_RNDN);
  mpfr_mul_2si(t, t, m - leading, MPFR_RNDN);
  const auto significand = static_cast<std::uint32_t>(mpfr_get_ui(t, MPFR_RNDN));
  return sign | (static_cast<std::uint32_t>(leading + bias) << m) | (significand & ((1u << m) - 1));
}

std::uint32_t canonical_nan(Format f) {
  return (((1u << f.exponent_bits) - 1) << f.fraction_bits) | (1u << (f.fraction_bits - 1));
}

}  // namespace

std::span<const OpInfo> all_ops() { return kOps; }

double to_double(Format f, std::uint32_t bits) {
  Scratch& s = scratch();
  decode(f, bits, s.x.get());
  return mpfr_get_d(s.x.get(), MPFR_RNDN);
}

std::uint32_t expected(Op op, Format f, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  Scratch& s = scratch();
  mpfr_ptr x = s.x.get();
  mpfr_ptr y = s.y.get();
  mpfr_ptr z = s.z.get();
  const mpfr_prec_t p = f.fraction_bits + 1;
  mpfr_ptr r = s.r.at(p);
  const auto rounded = [&](int (*fn)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t)) {
    decode(f, a, x);
    decode(f, b, y);
    fn(r, x, y, MPFR_RNDN);
    return encode(f, r);
  };
  const auto predicate = [&](int (*fn)(mpfr_srcptr, mpfr_srcptr)) {
    decode(f, a, x);
    decode(f, b, y);
    return static_cast<std::uint32_t>(fn(x, y) != 0);
  };
  switch (op) {
    case Op::kAdd: return rounded(mpfr_add);
    case Op::kSub: return rounded(mpfr_sub);
    case Op::kMul: return rounded(mpfr_mul);
    case Op::kDiv: return rounded(mpfr_div);
    case Op::kFma:
      decode(f, a, x);
      decode(f, b, y);
      decode(f, c, z);
      mpfr_fma(r, x, y, z, MPFR_RNDN);
      return encode(f, r);
    case Op::kRcp:
      decode(f, a, x);
      mpfr_ui_div(r, 1, x, MPFR_RNDN);
      return encode(f, r);
    case Op::kSqrt:
      decode(f, a, x);
      mpfr_sqrt(r, x, MPFR_RNDN);  // MPFR follows IEEE: sqrt(-0) = -0, sqrt(<0) = NaN
      return encode(f, r);
    case Op::kRsqrt: {
      // Defined as two correctly rounded steps, each with the range rules.
      const std::uint32_t root = expected(Op::kSqrt, f, a, 0, 0);
      return expected(Op::kRcp, f, root, 0, 0);
    }
    case Op::kMin:
    case Op::kMax:
      decode(f, a, x);
      decode(f, b, y);
      // The contract differs from MPFR (and IEEE minNum) here: NaN wins.
      if (mpfr_nan_p(x) || mpfr_nan_p(y)) return canonical_nan(f);
      // mpfr_min/max order -0 below +0, as the contract does.
      (op == Op::kMin ? mpfr_min : mpfr_max)(r, x, y, MPFR_RNDN);
      return encode(f, r);
    case Op::kFloor:
      decode(f, a, x);
      mpfr_floor(y, x);
      return encode(f, y);
    case Op::kFract:
      decode(f, a, x);
      mpfr_floor(y, x);
      mpfr_sub(r, x, y, MPFR_RNDN);
      return encode(f, r);
    case Op::kEq: return predicate(mpfr_equal_p);
    case Op::kNe: return 1 - predicate(mpfr_equal_p);
    case Op::kLt: return predicate(mpfr_less_p);
    case Op::kLe: return predicate(mpfr_lessequal_p);
    case Op::kGt: return predicate(mpfr_greater_p);
    case Op::kGe: return predicate(mpfr_greaterequal_p);
    case Op::kFromFp32:
      decode(kFp32, a, x);
      return encode(f, x);
    case Op::kToFp32:
      decode(f, a, x);
      return encode(kFp32, x);
    case Op::kFromInt32:
      mpfr_set_si(r, static_cast<std::int32_t>(a), MPFR_RNDN);
      return encode(f, r);
    case Op::kToInt32: {
      decode(f, a, x);
      if (mpfr_nan_p(x)) return 0;
      mpfr_trunc(y, x);
      std::int32_t value = 0;
      if (mpfr_cmp_si(y, std::numeric_limits<std::int32_t>::max()) > 0) {
        value = std::numeric_limits<std::int32_t>::max();
      } else if (mpfr_cmp_si(y, std::numeric_limits<std::int32_t>::min()) < 0) {
        value = std::numeric_limits<std::int32_t>::min();
      } else {
        value = static_cast<std::int32_t>(mpfr_get_si(y, MPFR_RNDZ));
      }
      return static_cast<std::uint32_t>(value);
    }
  }
  return 0;
}

}  // namespace rpu::fp::oracle
