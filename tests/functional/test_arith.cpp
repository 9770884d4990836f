// The sign operations of functional/arith.hpp, the one pair of arithmetic policies
// behind the shader cores and the trace units: the source modifiers neg and abs flip
// and clear the sign bit of every value but a NaN, which passes through unchanged
// (docs/numbers.md "Sign operations"; docs/shader-core.md "Values"). Checked on the
// soft path in every spec format and on the fp32 fast path, whose host negation would
// flip a NaN's sign.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "fp/fast32.hpp"
#include "fp/format.hpp"
#include "functional/arith.hpp"
#include "rpu/spec.hpp"

namespace rpu::functional {
namespace {

std::uint32_t bits_of(std::uint32_t v) { return v; }
std::uint32_t bits_of(float v) { return std::bit_cast<std::uint32_t>(v); }

// Every NaN in `nans` must come out of neg, abs and neg(abs) with its bits; every
// other value in `numbers` must have its sign bit flipped or cleared and nothing else.
template <class Arith>
void check_sign_rule(const Arith& ar, std::uint32_t sign_mask, const std::vector<typename Arith::Value>& nans,
                     const std::vector<typename Arith::Value>& numbers) {
  for (const auto x : nans) {
    const std::uint32_t b = bits_of(x);
    EXPECT_EQ(bits_of(ar.neg(x)), b) << fmt::format("neg of the NaN {:#x}", b);
    EXPECT_EQ(bits_of(ar.abs(x)), b) << fmt::format("abs of the NaN {:#x}", b);
    EXPECT_EQ(bits_of(ar.neg(ar.abs(x))), b) << fmt::format("-|x| of the NaN {:#x}", b);
  }
  for (const auto x : numbers) {
    const std::uint32_t b = bits_of(x);
    EXPECT_EQ(bits_of(ar.neg(x)), b ^ sign_mask) << fmt::format("neg of {:#x}", b);
    EXPECT_EQ(bits_of(ar.abs(x)), b & ~sign_mask) << fmt::format("abs of {:#x}", b);
  }
}

TEST(SignModifiers, LeaveANaNUnchangedOnTheSoftPathInEveryFormat) {
  for (const spec::FormatSpec& s : spec::kFormats) {
    const fp::Format f{s.exponent_bits, s.fraction_bits};
    SCOPED_TRACE(std::string(s.name));
    const SoftArith ar{f};
    const std::uint32_t nan = f.canonical_nan(), sign = f.sign_mask();
    const std::uint32_t inf = f.infinity(false);
    // The canonical NaN, what the arithmetic makes of inf - inf, and NaNs of either
    // sign with other payloads (a Value is any bit pattern of the format's width).
    const std::vector<std::uint32_t> nans = {nan, nan | sign, ar.sub(inf, inf), inf | 1, inf | 1 | sign,
                                             f.all_bits(), f.all_bits() & ~sign};
    std::vector<std::uint32_t> numbers;
    for (const bool negative : {false, true}) {
      for (const std::uint32_t v :
           {f.zero(negative), f.one(negative), f.infinity(negative), f.max_finite(negative), f.min_normal(negative)}) {
        numbers.push_back(v);
      }
    }
    check_sign_rule(ar, sign, nans, numbers);
  }
}

TEST(SignModifiers, LeaveANaNUnchangedOnTheFp32FastPath) {
  const fp::fast32::FlushScope flush;
  const Fast32Arith ar;
  const float inf = ar.load(0x7f800000u);
  // Host float makes NaNs of its own: x86's inf - inf is 0xffc00000, sign bit set.
  const std::vector<float> nans = {ar.load(0x7fc00000u), ar.load(0xffc00000u), ar.sub(inf, inf),
                                   ar.mul(ar.zero(), inf), ar.load(0x7f800001u), ar.load(0xffffffffu)};
  std::vector<float> numbers;
  for (const std::uint32_t v : {0x00000000u, 0x3f800000u, 0x7f800000u, 0x7f7fffffu, 0x00800000u}) {
    numbers.push_back(ar.load(v));
    numbers.push_back(ar.load(v | 0x80000000u));
  }
  check_sign_rule(ar, 0x80000000u, nans, numbers);
}

// Both policies store the same fp32 bits after the modifiers, NaN or not.
TEST(SignModifiers, StoreTheSameBitsOnBothFp32Paths) {
  const fp::fast32::FlushScope flush;
  const SoftArith soft{fp::kFp32};
  const Fast32Arith fast;
  for (const std::uint32_t v : {0x00000000u, 0x80000000u, 0x3f800000u, 0xbfc00000u, 0x7f800000u, 0xff800000u,
                                0x7fc00000u, 0xffc00000u, 0x7f800001u, 0x00000001u, 0x80000001u}) {
    EXPECT_EQ(fast.store(fast.neg(fast.load(v))), soft.store(soft.neg(soft.load(v)))) << fmt::format("-{:#x}", v);
    EXPECT_EQ(fast.store(fast.abs(fast.load(v))), soft.store(soft.abs(soft.load(v)))) << fmt::format("|{:#x}|", v);
  }
}

}  // namespace
}  // namespace rpu::functional
