#pragma once

#include <cstdint>
#include <span>

namespace rpu::progen {

// The generator's random numbers: SplitMix64 (Steele, Lea, Flood 2014, the seeding
// generator of java.util.SplittableRandom). Its own code rather than <random>'s
// distributions, whose output differs between standard libraries: a seed must name the
// same program on every host, so that anyone can reproduce a failing one. It does so for
// one compiler: the generator still passes several draws as one call's arguments, whose
// order C++ leaves open, so a GCC build and a clang build make different programs.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint32_t u32() { return static_cast<std::uint32_t>(next() >> 32); }
  // Uniform in [0, n) for n > 0 (the modulo bias of a 64-bit draw is below 2^-40 here).
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }
  // Uniform in [lo, hi].
  int range(int lo, int hi) { return lo + static_cast<int>(below(static_cast<std::uint32_t>(hi - lo + 1))); }
  // True with probability percent / 100.
  bool chance(int percent) { return below(100) < static_cast<std::uint32_t>(percent); }
  template <class T>
  const T& pick(std::span<const T> items) {
    return items[below(static_cast<std::uint32_t>(items.size()))];
  }

 private:
  std::uint64_t state_;
};

}  // namespace rpu::progen
