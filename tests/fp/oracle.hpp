#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "fp/format.hpp"

// The MPFR reference for the number contract (docs/numbers.md). It shares no code
// with rpu::fp: inputs are decoded here, each operation is computed by MPFR with
// M+1 bits of precision and an exponent range far wider than any format's (so the
// result is the correctly rounded one with unbounded exponent), and only then are
// the overflow and flush-to-zero rules applied.
namespace rpu::fp::oracle {

enum class Op {
  kAdd, kSub, kMul, kFma, kDiv, kRcp, kSqrt, kRsqrt, kMin, kMax, kFloor, kFract,
  kEq, kNe, kLt, kLe, kGt, kGe, kFromFp32, kToFp32, kFromInt32, kToInt32,
};

enum class Result { kValue, kBool, kInt32 };

struct OpInfo {
  Op op;
  std::string_view name;
  int arity;
  Result result;
};

std::span<const OpInfo> all_ops();

// Every result is returned as a uint32: format bits, 0/1 for a comparison, the
// two's complement bits of an int32. Operands beyond the arity are ignored; for
// kFromFp32 `a` holds fp32 bits and for kFromInt32 the int32's bits.
std::uint32_t expected(Op op, Format f, std::uint32_t a, std::uint32_t b, std::uint32_t c);

// The exact value of format bits (after the input flush) as a double, for messages.
double to_double(Format f, std::uint32_t bits);

}  // namespace rpu::fp::oracle
