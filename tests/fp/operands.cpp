#include "operands.hpp"

#include <limits>
#include <optional>
#include <utility>

namespace rpu::fp {
namespace {

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

}  // namespace

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


}  // namespace rpu::fp
