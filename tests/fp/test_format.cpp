// Format encoding helpers, name lookup, and contract rules spelled out with
// hand-computed bit patterns (independent of both the code and the MPFR oracle).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>

#include "common/error.hpp"
#include "fp/fast32.hpp"
#include "fp/format.hpp"
#include "fp/soft.hpp"

namespace rpu::fp {
namespace {

constexpr Format kFp16{5, 10};

TEST(Format, Fp32EncodingConstants) {
  EXPECT_EQ(kFp32.width(), 32);
  EXPECT_EQ(kFp32.bias(), 127);
  EXPECT_EQ(kFp32.max_finite(false), 0x7F7FFFFFu);
  EXPECT_EQ(kFp32.min_normal(true), 0x80800000u);
  EXPECT_EQ(kFp32.infinity(true), 0xFF800000u);
  EXPECT_EQ(kFp32.canonical_nan(), 0x7FC00000u);
  EXPECT_EQ(kFp32.one(false), 0x3F800000u);
}

TEST(Format, Fp16EncodingConstants) {
  EXPECT_EQ(kFp16.width(), 16);
  EXPECT_EQ(kFp16.max_finite(false), 0x7BFFu);
  EXPECT_EQ(kFp16.canonical_nan(), 0x7E00u);
}

TEST(Format, LookupBySpecNameAndShape) {
  EXPECT_EQ(format_by_name("fp32"), kFp32);
  EXPECT_EQ(format_by_name("rpu24"), (Format{7, 16}));
  EXPECT_EQ(format_by_name("bf16"), (Format{8, 7}));
  EXPECT_EQ(format_by_name("E5M10"), kFp16);
  EXPECT_EQ(format_by_name("E2M1"), (Format{2, 1}));
  EXPECT_EQ(format_by_name(Format{8, 15}.name()), (Format{8, 15}));
}

TEST(Format, UnknownNameListsTheKnownOnes) {
  for (const char* bad : {"fp64", "E9M10", "E8M24", "E1M3", "E8M", "EM8", "E8M7x", ""}) {
    try {
      format_by_name(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(std::string("'") + bad + "'"), std::string::npos) << message;
      EXPECT_NE(message.find("fp32, e8m15, rpu24, bf16, fp16"), std::string::npos) << message;
    }
  }
}

// fp32 cases of the contract with expected bits written out by hand, on both paths.
struct Case {
  const char* rule;
  std::uint32_t (*soft_op)(std::uint32_t, std::uint32_t);
  std::uint32_t (*fast_op)(std::uint32_t, std::uint32_t);
  std::uint32_t a, b, want;
};

std::uint32_t soft_add(std::uint32_t a, std::uint32_t b) { return soft::add(kFp32, a, b); }
std::uint32_t soft_mul(std::uint32_t a, std::uint32_t b) { return soft::mul(kFp32, a, b); }
std::uint32_t soft_div(std::uint32_t a, std::uint32_t b) { return soft::div(kFp32, a, b); }
std::uint32_t soft_min(std::uint32_t a, std::uint32_t b) { return soft::min(kFp32, a, b); }

TEST(Contract, Fp32HandWorkedCases) {
  const Case cases[] = {
      {"1 + 2^-24 ties to even 1", soft_add, fast32::add, 0x3F800000u, 0x33800000u, 0x3F800000u},
      {"(1+ulp) + 2^-24 ties to even 1+2ulp", soft_add, fast32::add, 0x3F800001u, 0x33800000u, 0x3F800002u},
      {"x + (-x) = +0", soft_add, fast32::add, 0xBF800000u, 0x3F800000u, 0x00000000u},
      {"(-0) + (-0) = -0", soft_add, fast32::add, 0x80000000u, 0x80000000u, 0x80000000u},
      {"subnormal input reads as zero", soft_add, fast32::add, 0x00000001u, 0x80000000u, 0x00000000u},
      {"tiny difference flushes to +0", soft_add, fast32::add, 0x00800001u, 0x80800000u, 0x00000000u},
      {"max + max overflows to inf", soft_add, fast32::add, 0x7F7FFFFFu, 0x7F7FFFFFu, 0x7F800000u},
      {"inf - inf is NaN", soft_add, fast32::add, 0x7F800000u, 0xFF800000u, 0x7FC00000u},
      {"NaN payload is not propagated", soft_add, fast32::add, 0xFFC00001u, 0x3F800000u, 0x7FC00000u},
      {"0 * inf is NaN", soft_mul, fast32::mul, 0x00000000u, 0x7F800000u, 0x7FC00000u},
      // (1 - 2^-24) * -2^-126 is exact in 24 bits and below 2^-126: flushed, sign kept.
      {"pred(1) * min normal flushes, sign kept", soft_mul, fast32::mul, 0x3F7FFFFFu, 0x80800000u, 0x80000000u},
      // (2^-1 + 2^-24) * (2^-125 - 2^-148) = 2^-126 * (1 - 2^-46): tiny before
      // rounding, but rounds to 2^-126 in 24 bits, so not tiny after rounding.
      {"rounds up to min normal: not flushed", soft_mul, fast32::mul, 0x3F000001u, 0x00FFFFFEu, 0x00800000u},
      {"1/0 = +inf", soft_div, fast32::div, 0x3F800000u, 0x00000000u, 0x7F800000u},
      {"1/(-subnormal) = -inf", soft_div, fast32::div, 0x3F800000u, 0x80000001u, 0xFF800000u},
      {"0/0 is NaN", soft_div, fast32::div, 0x00000000u, 0x80000000u, 0x7FC00000u},
      {"min(+0, -0) = -0", soft_min, fast32::min, 0x00000000u, 0x80000000u, 0x80000000u},
      {"min(NaN, 1) is NaN", soft_min, fast32::min, 0x7FC00000u, 0x3F800000u, 0x7FC00000u},
  };
  const fast32::FlushScope flush_mode;
  for (const Case& c : cases) {
    EXPECT_EQ(c.soft_op(c.a, c.b), c.want) << "soft: " << c.rule;
    EXPECT_EQ(c.fast_op(c.a, c.b), c.want) << "fast32: " << c.rule;
  }
}

TEST(Contract, Fp32UnaryAndConversionCases) {
  const fast32::FlushScope flush_mode;
  EXPECT_EQ(soft::sqrt(kFp32, 0x80000000u), 0x80000000u);   // sqrt(-0) = -0
  EXPECT_EQ(soft::sqrt(kFp32, 0xBF800000u), 0x7FC00000u);   // sqrt(-1) is NaN
  EXPECT_EQ(soft::rsqrt(kFp32, 0x40800000u), 0x3F000000u);  // 1/sqrt(4) = 0.5
  EXPECT_EQ(soft::floor(kFp32, 0xBF000000u), 0xBF800000u);  // floor(-0.5) = -1
  EXPECT_EQ(soft::floor(kFp32, 0x80000001u), 0x80000000u);  // floor(-subnormal) = -0
  EXPECT_EQ(fast32::floor(0x80000001u), 0x80000000u);
  EXPECT_EQ(soft::fract(kFp32, 0xB3000000u), 0x3F800000u);  // fract(-2^-25) rounds to 1.0
  EXPECT_EQ(fast32::fract(0xB3000000u), 0x3F800000u);
  EXPECT_EQ(soft::fract(kFp32, 0x7F800000u), 0x7FC00000u);  // fract(inf) is NaN
  EXPECT_EQ(soft::from_int32(kFp32, 16777217), 0x4B800000u);  // 2^24 + 1 ties to 2^24
  EXPECT_EQ(soft::from_int32(kFp32, std::numeric_limits<std::int32_t>::min()), 0xCF000000u);
  EXPECT_EQ(soft::to_int32(kFp32, 0x4F000000u), std::numeric_limits<std::int32_t>::max());  // 2^31
  EXPECT_EQ(soft::to_int32(kFp32, 0xCF000000u), std::numeric_limits<std::int32_t>::min());  // -2^31
  EXPECT_EQ(soft::to_int32(kFp32, 0xBFF00000u), -1);  // -1.875 truncates to -1
  EXPECT_EQ(soft::to_int32(kFp32, 0x7FC00000u), 0);
  EXPECT_EQ(fast32::to_int32(0x7FC00000u), 0);
  EXPECT_TRUE(soft::eq(kFp32, 0x80000000u, 0x00000001u));  // -0 == subnormal
  EXPECT_TRUE(soft::ne(kFp32, 0x7FC00000u, 0x7FC00000u));
  EXPECT_FALSE(fast32::le(0x7FC00000u, 0x7FC00000u));
  // fp32 -> fp16: 65520 is halfway between 65504 (max, odd) and 65536: ties to
  // even, which is the overflow to inf; 2^-14 * (1 - 2^-12) rounds up to 2^-14.
  EXPECT_EQ(soft::from_fp32(kFp16, 0x477FF000u), 0x7C00u);
  EXPECT_EQ(soft::from_fp32(kFp16, 0x387FF800u), 0x0400u);
  EXPECT_EQ(soft::from_fp32(kFp16, 0x387FC000u), 0x0000u);  // 2^-14 * (1 - 2^-9): tiny
  EXPECT_EQ(soft::to_fp32(kFp16, 0x3C00u), 0x3F800000u);
  EXPECT_EQ(soft::to_fp32(kFp16, 0x8001u), 0x80000000u);    // subnormal reads as -0
}

// scale_fp32 (kd space, docs/traversal.md §1) against std::ldexp in double, which is
// exact for fp32 values, then the contract's flushing: hand cases, then random bits
// (every class, both signs) times random powers of two.
std::uint32_t ldexp_flushed(std::uint32_t bits, int e) {
  const float x = std::bit_cast<float>(bits);
  const bool negative = (bits >> 31) != 0;
  if (std::isnan(x) || std::isinf(x)) return bits;
  const std::uint32_t zero = negative ? 0x80000000u : 0u;
  if (std::fpclassify(x) != FP_NORMAL) return zero;
  const double r = std::ldexp(double(x), e);
  if (std::abs(r) < double(std::numeric_limits<float>::min())) return zero;
  if (std::abs(r) > double(std::numeric_limits<float>::max())) return zero | 0x7f800000u;
  return std::bit_cast<std::uint32_t>(static_cast<float>(r));
}

TEST(Format, ScaleFp32IsExactWithFlushing) {
  EXPECT_EQ(scale_fp32(0x3F800000u, 9), 0x44000000u);     // 1 * 2^9 = 512
  EXPECT_EQ(scale_fp32(0xC4000000u, -9), 0xBF800000u);    // -512 * 2^-9 = -1
  EXPECT_EQ(scale_fp32(0x00800000u, -1), 0x00000000u);    // 2^-126 / 2 is subnormal: +0
  EXPECT_EQ(scale_fp32(0x80800000u, -1), 0x80000000u);    // -0 for a negative one
  EXPECT_EQ(scale_fp32(0x00000001u, 100), 0x00000000u);   // a subnormal input reads as +0
  EXPECT_EQ(scale_fp32(0x7F7FFFFFu, 1), 0x7F800000u);     // past the largest finite: inf
  EXPECT_EQ(scale_fp32(0xFF800000u, -5), 0xFF800000u);    // -inf stays
  EXPECT_EQ(scale_fp32(0x7FC00001u, 3), 0x7FC00001u);     // NaN passes unchanged
  EXPECT_EQ(scale_fp32(0x3F800000u, 127), 0x7F000000u);   // 2^127
  EXPECT_EQ(scale_fp32(0x3F800000u, -126), 0x00800000u);  // 2^-126
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int i = 0; i < 1000000; ++i) {
    const std::uint32_t bits = rng();
    const int e = i % 4 == 0 ? exponent(rng) : exponent(rng) % 20;
    ASSERT_EQ(scale_fp32(bits, e), ldexp_flushed(bits, e)) << std::hex << bits << std::dec << " * 2^" << e;
  }
}

}  // namespace
}  // namespace rpu::fp
