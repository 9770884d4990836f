// rpu::fp::soft in every spec format, and rpu::fp::fast32 for fp32, held bit for
// bit to the MPFR oracle (oracle.hpp) on edge classes, constructed cases and random
// operands. RPU_FP_RANDOM_COUNT sets the number of random operand sets per op and
// format (default 10^6; the `slow` ctest entries use 10^8). Besides the spec formats,
// a few extreme shapes (E2M1, E3M2, E8M1, E6M23) check that the soft path is generic.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fp/fast32.hpp"
#include "fp/format.hpp"
#include "fp/soft.hpp"
#include "oracle.hpp"
#include "rpu/spec.hpp"

namespace rpu::fp {
namespace {

using oracle::Op;
using oracle::OpInfo;

struct Operands {
  std::uint32_t a, b, c;
};

std::uint32_t soft_result(Op op, Format f, const Operands& v) {
  const auto as_bits = [](std::int32_t i) { return static_cast<std::uint32_t>(i); };
  switch (op) {
    case Op::kAdd: return soft::add(f, v.a, v.b);
    case Op::kSub: return soft::sub(f, v.a, v.b);
    case Op::kMul: return soft::mul(f, v.a, v.b);
    case Op::kFma: return soft::fma(f, v.a, v.b, v.c);
    case Op::kDiv: return soft::div(f, v.a, v.b);
    case Op::kRcp: return soft::rcp(f, v.a);
    case Op::kSqrt: return soft::sqrt(f, v.a);
    case Op::kRsqrt: return soft::rsqrt(f, v.a);
    case Op::kMin: return soft::min(f, v.a, v.b);
    case Op::kMax: return soft::max(f, v.a, v.b);
    case Op::kFloor: return soft::floor(f, v.a);
    case Op::kFract: return soft::fract(f, v.a);
    case Op::kEq: return soft::eq(f, v.a, v.b);
    case Op::kNe: return soft::ne(f, v.a, v.b);
    case Op::kLt: return soft::lt(f, v.a, v.b);
    case Op::kLe: return soft::le(f, v.a, v.b);
    case Op::kGt: return soft::gt(f, v.a, v.b);
    case Op::kGe: return soft::ge(f, v.a, v.b);
    case Op::kFromFp32: return soft::from_fp32(f, v.a);
    case Op::kToFp32: return soft::to_fp32(f, v.a);
    case Op::kFromInt32: return soft::from_int32(f, static_cast<std::int32_t>(v.a));
    case Op::kToInt32: return as_bits(soft::to_int32(f, v.a));
  }
  return 0;
}

std::uint32_t fast_result(Op op, const Operands& v) {
  const auto as_bits = [](std::int32_t i) { return static_cast<std::uint32_t>(i); };
  switch (op) {
    case Op::kAdd: return fast32::add(v.a, v.b);
    case Op::kSub: return fast32::sub(v.a, v.b);
    case Op::kMul: return fast32::mul(v.a, v.b);
    case Op::kFma: return fast32::fma(v.a, v.b, v.c);
    case Op::kDiv: return fast32::div(v.a, v.b);
    case Op::kRcp: return fast32::rcp(v.a);
    case Op::kSqrt: return fast32::sqrt(v.a);
    case Op::kRsqrt: return fast32::rsqrt(v.a);
    case Op::kMin: return fast32::min(v.a, v.b);
    case Op::kMax: return fast32::max(v.a, v.b);
    case Op::kFloor: return fast32::floor(v.a);
    case Op::kFract: return fast32::fract(v.a);
    case Op::kEq: return fast32::eq(v.a, v.b);
    case Op::kNe: return fast32::ne(v.a, v.b);
    case Op::kLt: return fast32::lt(v.a, v.b);
    case Op::kLe: return fast32::le(v.a, v.b);
    case Op::kGt: return fast32::gt(v.a, v.b);
    case Op::kGe: return fast32::ge(v.a, v.b);
    case Op::kFromFp32: return fast32::from_fp32(v.a);
    case Op::kToFp32: return fast32::to_fp32(v.a);
    case Op::kFromInt32: return fast32::from_int32(static_cast<std::int32_t>(v.a));
    case Op::kToInt32: return as_bits(fast32::to_int32(v.a));
  }
  return 0;
}

// The format an operand of `op` is encoded in (from_fp32 takes fp32 bits).
Format input_format(Op op, Format f) { return op == Op::kFromFp32 ? kFp32 : f; }

std::string describe_operand(Op op, Format f, std::uint32_t bits) {
  char text[96];
  if (op == Op::kFromInt32) {
    std::snprintf(text, sizeof text, "0x%08" PRIx32 " (%" PRId32 ")", bits, static_cast<std::int32_t>(bits));
  } else {
    std::snprintf(text, sizeof text, "0x%0*" PRIx32 " (%.9g)", (input_format(op, f).width() + 3) / 4, bits,
                  oracle::to_double(input_format(op, f), bits));
  }
  return text;
}

std::string describe_result(const OpInfo& info, Format f, std::uint32_t bits) {
  char text[96];
  if (info.result == oracle::Result::kBool) {
    std::snprintf(text, sizeof text, "%s", bits != 0 ? "true" : "false");
  } else if (info.result == oracle::Result::kInt32) {
    std::snprintf(text, sizeof text, "%" PRId32, static_cast<std::int32_t>(bits));
  } else {
    const Format out = info.op == Op::kToFp32 ? kFp32 : f;
    std::snprintf(text, sizeof text, "0x%0*" PRIx32 " (%.9g)", (out.width() + 3) / 4, bits,
                  oracle::to_double(out, bits));
  }
  return text;
}

// Compares soft (and, for fp32, fast32) with the oracle; prints the first few
// mismatches in full and counts the rest.
class Checker {
 public:
  Checker(const OpInfo& info, Format f, std::string_view format_name)
      : info_(info), format_(f), format_name_(format_name), check_fast_(f == kFp32) {}

  void check(const Operands& v) {
    ++checked_;
    const std::uint32_t want = oracle::expected(info_.op, format_, v.a, v.b, v.c);
    compare("soft", v, want, soft_result(info_.op, format_, v));
    if (check_fast_) compare("fast32", v, want, fast_result(info_.op, v));
  }

  ~Checker() {
    if (failures_ > kShown) {
      ADD_FAILURE() << info_.name << " " << format_name_ << ": " << failures_ << " mismatches in " << checked_
                    << " checks (first " << kShown << " shown)";
    }
  }
  Checker(const Checker&) = delete;
  Checker& operator=(const Checker&) = delete;

 private:
  static constexpr int kShown = 10;

  void compare(const char* path, const Operands& v, std::uint32_t want, std::uint32_t got) {
    if (want == got) return;
    if (++failures_ > kShown) return;
    std::ostringstream message;
    message << path << " " << info_.name << " " << format_name_ << " (" << format_.name() << ")";
    const std::array operands{v.a, v.b, v.c};
    for (int i = 0; i < info_.arity; ++i) {
      message << "\n  " << static_cast<char>('a' + i) << " = " << describe_operand(info_.op, format_, operands[i]);
    }
    message << "\n  expected " << describe_result(info_, format_, want) << "\n  actual   "
            << describe_result(info_, format_, got);
    ADD_FAILURE() << message.str();
  }

  const OpInfo& info_;
  Format format_;
  std::string_view format_name_;
  bool check_fast_;
  std::int64_t checked_ = 0;
  std::int64_t failures_ = 0;
};

// Values from every edge class of the format: zeros, subnormals (which must read as
// zero), the smallest normals and their neighbours, values around 1, the largest
// finite values, infinities and NaNs with various payloads and signs.
std::vector<std::uint32_t> edge_values(Format f) {
  const std::uint32_t min_normal = f.min_normal(false);
  const std::uint32_t one = f.one(false);
  const std::uint32_t max_finite = f.max_finite(false);
  const std::uint32_t half_exponent_up = static_cast<std::uint32_t>(f.bias() + f.bias() / 2) << f.fraction_bits;
  const std::uint32_t half_exponent_down = static_cast<std::uint32_t>(f.bias() / 2 + 1) << f.fraction_bits;
  const std::vector<std::uint32_t> magnitudes{
      0,
      1,                              // smallest subnormal
      f.fraction_mask(),              // largest subnormal
      min_normal,
      min_normal + 1,
      2 * min_normal - 1,             // largest value of the smallest binade
      2 * min_normal,
      one - 1,                        // just below 1
      one,
      one + 1,
      one + (1u << f.fraction_bits),  // 2
      one + (1u << (f.fraction_bits - 1)),                         // 1.5
      one + (1u << f.fraction_bits) + (1u << (f.fraction_bits - 1)),  // 3
      one - (1u << f.fraction_bits),  // 0.5
      half_exponent_up,
      half_exponent_up + 1,
      half_exponent_down,
      half_exponent_down - 1,
      max_finite - 1,
      max_finite,
      max_finite & ~f.fraction_mask(),  // largest power of two
      f.infinity(false),
  };
  std::vector<std::uint32_t> values;
  for (std::uint32_t m : magnitudes) {
    values.push_back(m);
    values.push_back(m | f.sign_mask());
  }
  const std::uint32_t quiet_bit = 1u << (f.fraction_bits - 1);
  values.push_back(f.canonical_nan());
  values.push_back(f.canonical_nan() | f.sign_mask());  // the x86 default NaN's shape
  values.push_back(f.exponent_mask() | 1);              // signalling, payload 1
  values.push_back(f.exponent_mask() | f.fraction_mask() | f.sign_mask());
  values.push_back(f.exponent_mask() | quiet_bit | 1);
  return values;
}

// Significands sa, sb in [2^m, 2^(m+1)) with 2^(2m+1) - 2^(m-3) < sa*sb < 2^(2m+1):
// their product, as a value, is below a power of two by less than a quarter of the
// half ulp there, so it rounds up across the binade boundary. Found by search; none
// exist for m < 3.
std::optional<std::pair<std::uint32_t, std::uint32_t>> significands_with_product_just_below_two(int m) {
  if (m < 3) return std::nullopt;
  const std::uint64_t target = std::uint64_t{1} << (2 * m + 1);
  const std::uint64_t window = std::uint64_t{1} << (m - 3);
  for (std::uint64_t sa = (std::uint64_t{1} << m) + 1; sa < (std::uint64_t{2} << m); ++sa) {
    const std::uint64_t sb = target / sa;
    if (sa * sb != target && target - sa * sb < window) {
      return std::pair{static_cast<std::uint32_t>(sa), static_cast<std::uint32_t>(sb)};
    }
  }
  return std::nullopt;
}

// Cases that random operands rarely reach, built per format.
std::vector<Operands> constructed(Op op, Format f) {
  const int m = f.fraction_bits;
  const std::uint32_t one = f.one(false);
  const std::uint32_t sign = f.sign_mask();
  // Out of range powers become zero or infinity, so small formats stay valid.
  const auto power_of_two = [&](int exponent) {
    return static_cast<std::uint32_t>(std::clamp(exponent + f.bias(), 0, static_cast<int>(f.exponent_field_max())))
           << m;
  };
  std::vector<Operands> cases;
  switch (op) {
    case Op::kAdd:
    case Op::kSub: {
      const std::uint32_t flip = op == Op::kSub ? sign : 0;
      // Ties: 1 + ulp/2 stays at 1 (even); (1 + ulp) + ulp/2 goes up to 1 + 2 ulp;
      // 1 - ulp/4 is halfway in the binade below and goes to 1.
      cases.push_back({one, power_of_two(-m - 1) ^ flip, 0});
      cases.push_back({one + 1, power_of_two(-m - 1) ^ flip, 0});
      cases.push_back({one, (power_of_two(-m - 2) | sign) ^ flip, 0});
      // Cancellation to exact zero in both operand orders and signs.
      for (std::uint32_t x : {one, one + 3, f.min_normal(false), f.max_finite(false)}) {
        cases.push_back({x, x ^ sign ^ flip, 0});
        cases.push_back({x | sign, x ^ flip, 0});
      }
      // Differences of neighbouring small normals are tiny and flush.
      cases.push_back({f.min_normal(false) + 1, f.min_normal(false) ^ flip ^ sign, 0});
      break;
    }
    case Op::kMul:
      // 3 * (1 + ulp) = 3 + 1.5 ulp(3): a tie, to even.
      cases.push_back({one + (3u << (m - 1)), one + 1, 0});
      cases.push_back({one + (3u << (m - 1)), one + 3, 0});
      // Products straddling the smallest normal and the largest finite.
      cases.push_back({one - 1, f.min_normal(false), 0});
      cases.push_back({one - 1, f.min_normal(false) + 1, 0});
      cases.push_back({one + 1, f.max_finite(false), 0});
      cases.push_back({one - 1, f.max_finite(false), 0});
      // A product just below the smallest normal that rounds up to it: not tiny after
      // rounding, so not flushed (x86 SSE FTZ must agree).
      if (const auto pair = significands_with_product_just_below_two(m)) {
        const std::uint32_t a = power_of_two(-1) | (pair->first & f.fraction_mask());
        const std::uint32_t b = power_of_two(f.min_exponent()) | (pair->second & f.fraction_mask());
        cases.push_back({a, b, 0});
        cases.push_back({a, b | sign, 0});
      }
      break;
    case Op::kFma:
      // a*b just below 2^(emin+1), minus the smallest normal: a result just below the
      // smallest normal that rounds up to it, so it is not tiny after rounding.
      if (const auto pair = significands_with_product_just_below_two(m)) {
        const std::uint32_t a = one | (pair->first & f.fraction_mask());
        const std::uint32_t b = power_of_two(f.min_exponent()) | (pair->second & f.fraction_mask());
        cases.push_back({a, b, f.min_normal(true)});
        cases.push_back({a | sign, b, f.min_normal(false)});
      }
      // The classic invalid and exact-zero cases.
      cases.push_back({0, f.infinity(false), f.canonical_nan()});
      cases.push_back({one, one, one | sign});
      cases.push_back({one | sign, one, one});
      cases.push_back({0 | sign, one, 0 | sign});
      break;
    case Op::kFromFp32: {
      // fp32 values at the format's rounding boundaries: ties, just below the
      // smallest normal (rounding up to it or not), around the overflow threshold.
      const int drop = 23 - m;
      const auto fp32_power = [](int exponent) { return static_cast<std::uint32_t>(std::clamp(exponent + 127, 0, 255)) << 23; };
      if (drop > 0) {
        const std::uint32_t half = 1u << (drop - 1);
        for (int e : {0, f.min_exponent() - 1, f.max_exponent()}) {
          cases.push_back({fp32_power(e) | half, 0, 0});
          cases.push_back({fp32_power(e) | (1u << drop) | half, 0, 0});
          cases.push_back({fp32_power(e) | 0x7FFFFFu, 0, 0});
          cases.push_back({fp32_power(e) | (0x7FFFFFu - half), 0, 0});
          cases.push_back({fp32_power(e) | (0x7FFFFFu & ~(2 * half - 1)) | half, 0, 0});
        }
      }
      for (int e : {f.min_exponent() - 2, f.min_exponent(), f.max_exponent() + 1}) {
        cases.push_back({fp32_power(e), 0, 0});
        cases.push_back({fp32_power(e) | 0x80000000u, 0, 0});
      }
      cases.push_back({1, 0, 0});  // an fp32 subnormal
      cases.push_back({0x7F800001u, 0, 0});
      cases.push_back({0xFFC00000u, 0, 0});
      break;
    }
    case Op::kFromInt32:
      for (std::int64_t v : {std::int64_t{0}, std::int64_t{1}, std::int64_t{-1},
                             std::int64_t{std::numeric_limits<std::int32_t>::max()},
                             std::int64_t{std::numeric_limits<std::int32_t>::min()},
                             (std::int64_t{1} << (m + 1)) + 1, (std::int64_t{1} << (m + 1)) + 3,
                             -((std::int64_t{1} << (m + 1)) + 1), (std::int64_t{1} << 30) - 1}) {
        cases.push_back({static_cast<std::uint32_t>(static_cast<std::int32_t>(v)), 0, 0});
      }
      break;
    case Op::kToInt32:
      for (int e : {30, 31, 32}) {
        if (e > f.max_exponent()) continue;
        cases.push_back({power_of_two(e), 0, 0});
        cases.push_back({power_of_two(e) | sign, 0, 0});
        cases.push_back({power_of_two(e) - 1, 0, 0});
        cases.push_back({(power_of_two(e) - 1) | sign, 0, 0});
        cases.push_back({power_of_two(e) + 1, 0, 0});
        cases.push_back({(power_of_two(e) + 1) | sign, 0, 0});
      }
      break;
    case Op::kFract:
      // A tiny negative value: 1 - tiny rounds to 1.0.
      cases.push_back({f.min_normal(true), 0, 0});
      cases.push_back({power_of_two(-m - 2) | sign, 0, 0});
      break;
    default:
      break;
  }
  return cases;
}

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

std::int64_t random_count() {
  const char* text = std::getenv("RPU_FP_RANDOM_COUNT");
  return text != nullptr ? std::strtoll(text, nullptr, 10) : 1'000'000;
}

using Param = std::tuple<OpInfo, std::string_view>;

// Every spec format, and extreme shapes the soft path must also handle.
std::vector<std::string_view> format_names() {
  std::vector<std::string_view> names;
  for (const spec::FormatSpec& f : spec::kFormats) names.push_back(f.name);
  for (std::string_view shape : {"E2M1", "E3M2", "E8M1", "E6M23"}) names.push_back(shape);
  return names;
}

}  // namespace
}  // namespace rpu::fp

// Readable parameters in `ctest -N` and gtest output (found by argument lookup).
namespace rpu::fp::oracle {
void PrintTo(const OpInfo& info, std::ostream* out) { *out << info.name; }
}  // namespace rpu::fp::oracle

namespace rpu::fp {
namespace {

class FpOp : public ::testing::TestWithParam<Param> {
 protected:
  const OpInfo& info() const { return std::get<0>(GetParam()); }
  std::string_view format_name() const { return std::get<1>(GetParam()); }
  Format format() const { return format_by_name(format_name()); }
};

TEST_P(FpOp, EdgeClassesMatchMpfr) {
  const fast32::FlushScope flush_mode;
  Checker checker(info(), format(), format_name());
  const Format f = format();
  // from_fp32 and from_int32 inputs are not format values: their edges are built in
  // constructed(); for the rest every combination of edge values is checked.
  if (info().op != Op::kFromFp32 && info().op != Op::kFromInt32) {
    const std::vector<std::uint32_t> edges = edge_values(f);
    for (std::uint32_t a : edges) {
      if (info().arity == 1) {
        checker.check({a, 0, 0});
        continue;
      }
      for (std::uint32_t b : edges) {
        if (info().arity == 2) {
          checker.check({a, b, 0});
          continue;
        }
        for (std::uint32_t c : edges) checker.check({a, b, c});
      }
    }
  }
  for (const Operands& v : constructed(info().op, f)) checker.check(v);
}

TEST_P(FpOp, RandomOperandsMatchMpfr) {
  const fast32::FlushScope flush_mode;
  Checker checker(info(), format(), format_name());
  // A fixed seed per op and format, so a failure reproduces.
  const auto seed = std::hash<std::string>{}(std::string(info().name) + "/" + std::string(format_name()));
  OperandSource source(info().op, format(), seed);
  const std::int64_t count = random_count();
  for (std::int64_t i = 0; i < count; ++i) checker.check(source.next());
}

std::string param_name(const ::testing::TestParamInfo<Param>& p) {
  return std::string(std::get<0>(p.param).name) + "_" + std::string(std::get<1>(p.param));
}

INSTANTIATE_TEST_SUITE_P(Fp, FpOp,
                         ::testing::Combine(::testing::ValuesIn(oracle::all_ops().begin(), oracle::all_ops().end()),
                                            ::testing::ValuesIn(format_names())),
                         param_name);

}  // namespace
}  // namespace rpu::fp
