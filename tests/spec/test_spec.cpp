// The generated spec header is consistent with itself and with the number contract.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string_view>

#include "rpu/spec.hpp"

namespace rpu::spec {
namespace {

TEST(Spec, FormatsFitTheSoftArithmeticLimits) {
  for (const FormatSpec& f : kFormats) {
    EXPECT_GE(f.exponent_bits, 2) << f.name;
    EXPECT_LE(f.exponent_bits, 8) << f.name;
    EXPECT_GE(f.fraction_bits, 1) << f.name;
    EXPECT_LE(f.fraction_bits, 23) << f.name;
  }
}

TEST(Spec, IssueFormatsArePresent) {
  // The accuracy study of issue 2 covers these five (E, M) pairs.
  const std::set<std::pair<int, int>> wanted{{8, 23}, {8, 15}, {7, 16}, {8, 7}, {5, 10}};
  std::set<std::pair<int, int>> have;
  for (const FormatSpec& f : kFormats) have.insert({f.exponent_bits, f.fraction_bits});
  for (auto w : wanted) EXPECT_TRUE(have.contains(w)) << "E" << w.first << "M" << w.second;
}

TEST(Spec, EveryConfigNamesAKnownFormat) {
  for (const HardwareConfig& c : kConfigs) {
    const bool known = std::any_of(kFormats.begin(), kFormats.end(),
                                   [&](const FormatSpec& f) { return f.name == c.format; });
    EXPECT_TRUE(known) << c.name << " uses " << c.format;
    EXPECT_EQ(c.threads_per_core % c.chunk_size, 0) << c.name;
  }
}

TEST(Spec, KdNodeWordSplitsIntoKindAndIndex) {
  EXPECT_EQ(memory::kKdNodeKindBits + memory::kKdNodeIndexBits, 32u);
  EXPECT_EQ(memory::kKdNodeBytes, 8u);
  EXPECT_LT(memory::kKdNodeLeafKind, 1u << memory::kKdNodeKindBits);
}

}  // namespace
}  // namespace rpu::spec
