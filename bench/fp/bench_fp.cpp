// Throughput of rpu::fp::soft (fp32) against rpu::fp::fast32, and the cost of
// setting MXCSR per operation instead of once per scope.
//
//   build/ci/bench/fp/bench_fp
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "fp/fast32.hpp"
#include "fp/format.hpp"
#include "fp/soft.hpp"

namespace rpu::fp {
namespace {

// Positive normal fp32 values in [2^-20, 2^20): no special cases, valid for sqrt.
const std::vector<std::uint32_t>& operands() {
  static const std::vector<std::uint32_t> values = [] {
    std::mt19937 rng(1);
    std::vector<std::uint32_t> v(4096);
    for (std::uint32_t& x : v) x = ((107 + rng() % 40) << 23) | (rng() & 0x7FFFFF);
    return v;
  }();
  return values;
}

enum class Flush { kScope, kPerCall };

template <typename Op>
void run(benchmark::State& state, Op op, Flush flush) {
  const std::vector<std::uint32_t>& v = operands();
  const std::size_t n = v.size();
  const fast32::FlushScope scope;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t a = v[i], b = v[(i + 1) % n], c = v[(i + 2) % n];
      if (flush == Flush::kPerCall) {
        const fast32::FlushScope per_call;
        benchmark::DoNotOptimize(op(a, b, c));
      } else {
        benchmark::DoNotOptimize(op(a, b, c));
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}

#define RPU_BENCH_OP(name, soft_call, fast_call)                                                   \
  void name##_soft(benchmark::State& s) {                                                          \
    run(s, [](std::uint32_t a, std::uint32_t b, std::uint32_t c) { return soft_call; }, Flush::kScope); \
  }                                                                                                \
  void name##_fast32(benchmark::State& s) {                                                        \
    run(s, [](std::uint32_t a, std::uint32_t b, std::uint32_t c) { return fast_call; }, Flush::kScope); \
  }                                                                                                \
  void name##_fast32_mxcsr_per_call(benchmark::State& s) {                                         \
    run(s, [](std::uint32_t a, std::uint32_t b, std::uint32_t c) { return fast_call; }, Flush::kPerCall); \
  }                                                                                                \
  BENCHMARK(name##_soft);                                                                          \
  BENCHMARK(name##_fast32);                                                                        \
  BENCHMARK(name##_fast32_mxcsr_per_call)

// Unused operands are still passed so every benchmark has the same loop.
RPU_BENCH_OP(add, ((void)c, soft::add(kFp32, a, b)), ((void)c, fast32::add(a, b)));
RPU_BENCH_OP(mul, ((void)c, soft::mul(kFp32, a, b)), ((void)c, fast32::mul(a, b)));
RPU_BENCH_OP(fma, soft::fma(kFp32, a, b, c), fast32::fma(a, b, c));
RPU_BENCH_OP(div, ((void)c, soft::div(kFp32, a, b)), ((void)c, fast32::div(a, b)));
RPU_BENCH_OP(sqrt, ((void)b, (void)c, soft::sqrt(kFp32, a)), ((void)b, (void)c, fast32::sqrt(a)));

}  // namespace
}  // namespace rpu::fp

BENCHMARK_MAIN();
