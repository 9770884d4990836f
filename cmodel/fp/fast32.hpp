#pragma once

#include <cstdint>

// The fp32 (E8M23) fast path: the same operations as rpu::fp::soft on fp32 bit
// patterns, computed with host float arithmetic and bit-identical to
// soft::op(kFp32, ...). The host must run with flush-to-zero and
// denormals-are-zero: hold a FlushScope on the calling thread while using these.
namespace rpu::fp::fast32 {

// Sets MXCSR.FTZ and MXCSR.DAZ for the life of the object on this thread and
// restores the previous MXCSR afterwards. One scope around a batch of operations
// is much cheaper than setting MXCSR per operation (docs/numbers.md, "Speed").
class FlushScope {
 public:
  FlushScope();
  ~FlushScope();
  FlushScope(const FlushScope&) = delete;
  FlushScope& operator=(const FlushScope&) = delete;

 private:
  unsigned int saved_;
};

// True if MXCSR has FTZ and DAZ set on this thread.
bool flush_mode_active();

std::uint32_t add(std::uint32_t a, std::uint32_t b);
std::uint32_t sub(std::uint32_t a, std::uint32_t b);
std::uint32_t mul(std::uint32_t a, std::uint32_t b);
std::uint32_t fma(std::uint32_t a, std::uint32_t b, std::uint32_t c);
std::uint32_t div(std::uint32_t a, std::uint32_t b);
std::uint32_t rcp(std::uint32_t a);
std::uint32_t sqrt(std::uint32_t a);
std::uint32_t rsqrt(std::uint32_t a);
std::uint32_t min(std::uint32_t a, std::uint32_t b);
std::uint32_t max(std::uint32_t a, std::uint32_t b);
std::uint32_t floor(std::uint32_t a);
std::uint32_t fract(std::uint32_t a);

bool eq(std::uint32_t a, std::uint32_t b);
bool ne(std::uint32_t a, std::uint32_t b);
bool lt(std::uint32_t a, std::uint32_t b);
bool le(std::uint32_t a, std::uint32_t b);
bool gt(std::uint32_t a, std::uint32_t b);
bool ge(std::uint32_t a, std::uint32_t b);

std::uint32_t from_fp32(std::uint32_t fp32_bits);
std::uint32_t to_fp32(std::uint32_t a);
std::uint32_t from_int32(std::int32_t value);
std::int32_t to_int32(std::uint32_t a);

std::uint32_t flush(std::uint32_t a);

}  // namespace rpu::fp::fast32
