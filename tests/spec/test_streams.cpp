// rpu/streams.hpp (spec/streams.toml): every stream's fields tile its bits from the most
// significant down, pack() and unpack() are inverse, and each field lands at the bits
// its layout says, across word boundaries. That the RTL sees the same bits is what the
// co-simulations show: a C++ order unlike the SV struct's fails them.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <tuple>

#include "rpu/streams.hpp"

namespace rpu::streams {
namespace {

template <class F>
void for_each_stream(F&& f) {
  std::apply([&](auto... s) { (f(s), ...); }, All{});
}

template <class S>
typename S::Words random_words(std::mt19937& rng) {
  typename S::Words w;
  for (auto& x : w) x = static_cast<std::uint32_t>(rng());
  if (S::kBits % 32) w.back() &= (std::uint32_t{1} << (S::kBits % 32)) - 1;  // no bits above kBits
  return w;
}

TEST(Streams, FieldsTileTheBitsFromTheTop) {
  for_each_stream([](auto s) {
    using S = decltype(s);
    int top = S::kBits;
    for (const FieldLayout& f : S::kLayout) {
      EXPECT_EQ(f.lsb + f.bits * f.count, top) << S::kName << "." << f.name;
      EXPECT_TRUE(f.count == 1 || f.bits == 32) << S::kName << "." << f.name;
      top = f.lsb;
    }
    EXPECT_EQ(top, 0) << S::kName;
    EXPECT_EQ(S::kWords, (S::kBits + 31) / 32) << S::kName;
  });
}

TEST(Streams, UnpackThenPackIsTheIdentity) {
  std::mt19937 rng(7);
  for_each_stream([&](auto s) {
    using S = decltype(s);
    for (int i = 0; i < 100; ++i) {
      const typename S::Words w = random_words<S>(rng);
      EXPECT_EQ(S::unpack(w).pack(), w) << S::kName;
      EXPECT_EQ(S::unpack(S::unpack(w).pack()), S::unpack(w)) << S::kName;
    }
  });
}

TEST(Streams, EachFieldSitsAtItsLayoutBits) {
  for_each_stream([](auto s) {
    using S = decltype(s);
    for (std::size_t i = 0; i < S::kLayout.size(); ++i) {
      const FieldLayout& f = S::kLayout[i];
      for (int k = 0; k < f.count; ++k) {
        // Only word k of field i set: its bits, and no other field's.
        typename S::Words w{};
        for (int b = f.lsb + 32 * k; b < f.lsb + 32 * k + f.bits; ++b) w[b / 32] |= std::uint32_t{1} << (b % 32);
        const S value = S::unpack(w);
        const auto fields = value.fields();
        for (std::size_t j = 0; j < fields.size(); ++j) {
          for (int m = 0; m < fields[j].count; ++m) {
            const std::uint32_t want =
                j == i && m == k ? (f.bits == 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << f.bits) - 1) : 0;
            EXPECT_EQ(fields[j].words[m], want) << S::kName << "." << f.name << "[" << k << "] set, read "
                                                << fields[j].name << "[" << m << "]";
          }
        }
        EXPECT_EQ(value.pack(), w) << S::kName << "." << f.name;
      }
    }
  });
}

TEST(Streams, PackMasksEachFieldToItsWidth) {
  TuRsp r;
  r.tag = ~std::uint32_t{0};
  r.hit = 3;  // 2 bits into 1
  const TuRsp back = TuRsp::unpack(r.pack());
  EXPECT_EQ(back.tag, (std::uint32_t{1} << kRayTagBits) - 1);
  EXPECT_EQ(back.hit, 1u);
}

}  // namespace
}  // namespace rpu::streams
