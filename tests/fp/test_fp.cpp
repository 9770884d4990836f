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
#include "operands.hpp"
#include "oracle.hpp"
#include "rpu/spec.hpp"

namespace rpu::fp {
namespace {

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
