#include "cc/select.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <spirv/unified1/GLSL.std.450.h>

#include "cc/math.hpp"
#include "cc/spirv_names.hpp"

namespace rpu::cc {

namespace {

using spv::Op;

// What one selection works on: the builder, the operands, the result's lanes and the op
// (a spv::Op or a GLSL.std.450 instruction).
struct Selection {
  Builder& b;
  Operands& in;
  int n;
  std::uint32_t op;
};

// Where one call takes several values that emit code (an operand's first read, a
// constant, an instruction), they are made first, into named locals, in the order the
// firmware has always had them: C++ leaves the order of a call's arguments unspecified
// (GCC evaluates them right to left, clang left to right), and the firmware must not
// depend on the compiler that built rpu. An instruction's sources in braces are made
// left to right, as a braced list is evaluated.

// An op that is one RPU instruction on its operands, in order or swapped, or the
// complement of that instruction's result (a mask: all ones or zero). SPIR-V gives these
// ops operands with as many components as the result, so no operand is broadcast.
struct Direct {
  Opcode opcode;
  std::optional<Opcode> with_constant = std::nullopt;  // the form with a constant second operand as its immediate
  bool shift = false;       // that constant is a shift count, taken mod 32 as the instruction takes it
  bool swap = false;        // a and b are the op's second and first operands
  bool complement = false;  // the op's result is the complement of the instruction's
};

int register_sources(Opcode opcode) {
  const isa::InsnSpec& spec = *isa::find_insn(opcode);
  const auto operands = std::span(spec.operands).first(static_cast<std::size_t>(spec.operand_count));
  return static_cast<int>(std::count_if(operands.begin(), operands.end(), [](isa::Operand o) {
    return o == isa::Operand::kA || o == isa::Operand::kB || o == isa::Operand::kC;
  }));
}

Src direct(Selection& s, const Direct& d) {
  if (d.with_constant) {
    if (const auto c = s.in.constant(1)) {
      const std::int64_t imm = d.shift ? std::int64_t{*c & 31} : static_cast<std::int32_t>(*c);
      return s.b.op(*d.with_constant, s.n, {s.in.value(0)}, Imm::integer(imm));
    }
  }
  std::vector<Src> srcs;
  for (int k = 0; k < register_sources(d.opcode); ++k) srcs.push_back(s.in.value(static_cast<std::size_t>(k)));
  if (d.swap) std::swap(srcs[0], srcs[1]);
  const Src r = s.b.op(d.opcode, s.n, std::move(srcs));
  return d.complement ? s.b.not_of(r) : r;
}

// ---- SPIR-V ops ---------------------------------------------------------------------------

constexpr std::pair<Op, Direct> kDirectOps[] = {
    {Op::OpFAdd, {Opcode::kAdd}},
    {Op::OpFMul, {Opcode::kMul}},
    // comparisons: masks. a > b is b < a; an unordered compare is the complement of the
    // ordered one it excludes (NaN makes every ordered compare false).
    {Op::OpFOrdEqual, {Opcode::kFeq}},
    {Op::OpFUnordNotEqual, {Opcode::kFne}},
    {Op::OpFOrdLessThan, {Opcode::kFlt}},
    {Op::OpFOrdGreaterThan, {.opcode = Opcode::kFlt, .swap = true}},
    {Op::OpFOrdLessThanEqual, {Opcode::kFle}},
    {Op::OpFOrdGreaterThanEqual, {.opcode = Opcode::kFle, .swap = true}},
    {Op::OpFUnordLessThan, {.opcode = Opcode::kFle, .swap = true, .complement = true}},
    {Op::OpFUnordGreaterThan, {.opcode = Opcode::kFle, .complement = true}},
    {Op::OpFUnordLessThanEqual, {.opcode = Opcode::kFlt, .swap = true, .complement = true}},
    {Op::OpFUnordGreaterThanEqual, {.opcode = Opcode::kFlt, .complement = true}},
    {Op::OpIEqual, {Opcode::kIeq}},
    {Op::OpINotEqual, {.opcode = Opcode::kIeq, .complement = true}},
    {Op::OpLogicalEqual, {Opcode::kIeq}},
    {Op::OpLogicalNotEqual, {Opcode::kXor}},
    {Op::OpSLessThan, {.opcode = Opcode::kIlt, .with_constant = Opcode::kIlti}},
    {Op::OpSGreaterThan, {.opcode = Opcode::kIlt, .swap = true}},
    {Op::OpSLessThanEqual, {.opcode = Opcode::kIlt, .swap = true, .complement = true}},
    {Op::OpSGreaterThanEqual, {.opcode = Opcode::kIlt, .complement = true}},
    {Op::OpULessThan, {Opcode::kIltu}},
    {Op::OpUGreaterThan, {.opcode = Opcode::kIltu, .swap = true}},
    {Op::OpULessThanEqual, {.opcode = Opcode::kIltu, .swap = true, .complement = true}},
    {Op::OpUGreaterThanEqual, {.opcode = Opcode::kIltu, .complement = true}},
    {Op::OpLogicalAnd, {Opcode::kAnd}},
    {Op::OpLogicalOr, {Opcode::kOr}},
    // integers
    {Op::OpIAdd, {.opcode = Opcode::kIadd, .with_constant = Opcode::kIaddi}},
    {Op::OpIMul, {.opcode = Opcode::kImul, .with_constant = Opcode::kImuli}},
    {Op::OpBitwiseAnd, {.opcode = Opcode::kAnd, .with_constant = Opcode::kAndi}},
    {Op::OpBitwiseOr, {.opcode = Opcode::kOr, .with_constant = Opcode::kOri}},
    {Op::OpBitwiseXor, {.opcode = Opcode::kXor, .with_constant = Opcode::kXori}},
    {Op::OpShiftLeftLogical, {.opcode = Opcode::kShl, .with_constant = Opcode::kShli, .shift = true}},
    {Op::OpShiftRightLogical, {.opcode = Opcode::kShr, .with_constant = Opcode::kShri, .shift = true}},
    {Op::OpShiftRightArithmetic, {.opcode = Opcode::kSra, .with_constant = Opcode::kSrai, .shift = true}},
    // conversions
    {Op::OpConvertSToF, {Opcode::kI2f}},
    {Op::OpConvertFToS, {Opcode::kF2i}},
};

Src subtract(Selection& s) { return s.b.op(Opcode::kAdd, s.n, {s.in.value(0), neg(s.in.value(1))}); }

Src fdiv(Selection& s) {
  const int n = s.n;
  if (const auto c = s.in.constant(0); c && *c == std::bit_cast<std::uint32_t>(1.0f)) {
    return s.b.op(Opcode::kRcp, n, {s.in.value(1)});  // 1 / y
  }
  const Src y = s.in.value(1);  // y read before x, as always
  const Src x = s.in.value(0);
  return divide(s.b, x, y, n);
}

Src negate(Selection& s) { return neg(s.in.value(0)); }  // a modifier on its uses

// x - y floor(x / y)
Src float_mod(Selection& s) {
  const int n = s.n;
  const Src x = s.in.value(0), y = s.in.value(1);
  const Src q = s.b.op(Opcode::kFlr, n, {divide(s.b, x, y, n)});
  return s.b.op(Opcode::kMad, n, {neg(y), q, x});
}

Src vector_times_scalar(Selection& s) {
  return s.b.op(Opcode::kMul, s.n, {s.in.value(0), broadcast(s.in.value(1), s.n)});
}

Src dot_product(Selection& s) {
  const Src y = s.in.value(1);  // y read before x, as always
  const Src x = s.in.value(0);
  return dot(s.b, x, y);
}

Src matrix_times_vector(Selection& s) {
  const int n = s.n;
  const std::vector<Src> m = s.in.columns(0);
  const Src v = s.in.value(1);
  Src acc = s.b.op(Opcode::kMul, n, {m.at(0), broadcast(component(v, 0), n)});
  for (std::size_t k = 1; k < m.size(); ++k) {
    acc = s.b.op(Opcode::kMad, n, {m[k], broadcast(component(v, static_cast<int>(k)), n), acc});
  }
  return acc;
}

Src vector_times_matrix(Selection& s) {
  const Src v = s.in.value(0);
  const std::vector<Src> m = s.in.columns(1);
  const int d = s.b.vreg(s.n);
  for (int k = 0; k < s.n; ++k) {
    const Src dk = dot(s.b, v, m.at(static_cast<std::size_t>(k)));
    s.b.op_into(d, static_cast<std::uint8_t>(1u << k), Opcode::kMov, {dk}, {}, k == 0);
  }
  return whole(d, s.n);
}

// a < b or b < a: false for NaN
Src ord_not_equal(Selection& s) {
  return s.b.op(Opcode::kOr, s.n, {direct(s, {Opcode::kFlt}), direct(s, {.opcode = Opcode::kFlt, .swap = true})});
}

Src unord_equal(Selection& s) { return s.b.not_of(ord_not_equal(s)); }

Src is_nan(Selection& s) {
  const Src a = s.in.value(0);
  return s.b.op(Opcode::kFne, s.n, {a, a});
}

Src is_inf(Selection& s) { return s.b.op(Opcode::kFeq, s.n, {abs(s.in.value(0)), s.b.fconst(INFINITY, s.n)}); }

Src complement(Selection& s) { return s.b.not_of(s.in.value(0)); }

Src any_or_all(Selection& s) {
  const Src v = s.in.value(0);
  Src r = component(v, 0);
  const Opcode combine = static_cast<Op>(s.op) == Op::OpAny ? Opcode::kOr : Opcode::kAnd;
  for (int k = 1; k < v.n; ++k) r = s.b.op(combine, 1, {r, component(v, k)});
  return r.v == v.v && v.n == 1 ? s.b.op(Opcode::kMov, 1, {r}) : r;
}

Src select_op(Selection& s) {
  // the operands read last to first, as always
  const Src on_false = s.in.value(2);
  const Src on_true = s.in.value(1);
  const Src cond = s.in.value(0);
  return s.b.select(cond, on_true, on_false, s.n);
}

Src isub(Selection& s) {
  if (const auto c = s.in.constant(1)) {
    return s.b.op(Opcode::kIaddi, s.n, {s.in.value(0)},
                  Imm::integer(-static_cast<std::int64_t>(static_cast<std::int32_t>(*c))));
  }
  return direct(s, {Opcode::kIsub});
}

Src snegate(Selection& s) {
  return s.b.op(Opcode::kIsub, s.n, {s.b.op(Opcode::kLi, s.n, {}, Imm::integer(0)), s.in.value(0)});
}

// (v ^ sign) - sign: v negated where sign is all ones, kept where it is 0; with v's own
// sign (srai 31), |v| as an unsigned value (|INT_MIN| = 2^31).
Src flip_sign(Builder& b, const Src& v, const Src& sign, int n) {
  return b.op(Opcode::kIsub, n, {b.op(Opcode::kXor, n, {v, sign}), sign});
}

// SMod from the remainder with the dividend's sign: a nonzero one whose sign differs
// from the divisor's moves by the divisor.
Src modulo_of_remainder(Builder& b, const Src& rem, const Src& divisor, int n) {
  const Src nonzero = b.not_of(b.op(Opcode::kIeq, n, {rem, b.op(Opcode::kLi, n, {}, Imm::integer(0))}));
  const Src differs = b.op(Opcode::kIlti, n, {b.op(Opcode::kXor, n, {rem, divisor})}, Imm::integer(0));
  const Src moved = b.op(Opcode::kIadd, n, {rem, divisor});
  return b.select(b.op(Opcode::kAnd, n, {nonzero, differs}), moved, rem, n);
}

// a / d, unsigned, for a constant d: a shift for a power of two, else Granlund and
// Montgomery's multiply by a magic number ("Division by Invariant Integers using
// Multiplication", PLDI 1994, figure 4.1), exact for every 32-bit a.
Src unsigned_quotient(Builder& b, const Src& a, std::uint32_t d, int n) {
  if (std::has_single_bit(d)) return b.op(Opcode::kShri, n, {a}, Imm::integer(std::countr_zero(d)));
  const int l = std::bit_width(d - 1);  // ceil(log2 d), 2..32
  const std::uint64_t magic = (std::uint64_t{1} << 32) * ((std::uint64_t{1} << l) - d) / d + 1;
  const Src m = b.op(Opcode::kLi, n, {}, Imm::bits(static_cast<std::uint32_t>(magic)));
  const Src t = b.op(Opcode::kImulhu, n, {a, m});
  const Src half = b.op(Opcode::kShri, n, {b.op(Opcode::kIsub, n, {a, t})}, Imm::integer(1));
  return b.op(Opcode::kShri, n, {b.op(Opcode::kIadd, n, {t, half})}, Imm::integer(l - 1));
}

// a / d, unsigned, for a d known only when the shader runs: restoring division, one
// quotient bit a trip for 32 trips (every lane the same count), exact for every a and d;
// d = 0 gives all ones. The remainder is left in `remainder`.
Src unsigned_quotient_of(Builder& b, const Src& a_in, const Src& d, int n, Src& remainder) {
  const Src zero = b.op(Opcode::kLi, n, {}, Imm::integer(0));
  const int a = b.vreg(n), q = b.vreg(n), r = b.vreg(n), trips = b.vreg(1);
  b.op_into(a, 0, Opcode::kMov, {a_in}, {}, true);
  b.op_into(q, 0, Opcode::kMov, {zero}, {}, true);
  b.op_into(r, 0, Opcode::kMov, {zero}, {}, true);
  b.op_into(trips, 0, Opcode::kLi, {}, Imm::integer(32), true);
  const std::string top = b.fresh_label("divide");
  b.label(top);
  // r:a shifted left one bit; r's bit shifted out (carry) means r is past any d.
  const Src carry = b.op(Opcode::kSrai, n, {b.whole(r)}, Imm::integer(31));
  const Src next_bit = b.op(Opcode::kShri, n, {b.whole(a)}, Imm::integer(31));
  const Src shifted = b.op(Opcode::kOr, n, {b.op(Opcode::kShli, n, {b.whole(r)}, Imm::integer(1)), next_bit});
  b.op_into(a, 0, Opcode::kShli, {b.whole(a)}, Imm::integer(1));
  const Src below = b.op(Opcode::kIltu, n, {shifted, d});
  const Src fits = b.op(Opcode::kOr, n, {carry, b.not_of(below)});
  const Src less_d = b.op(Opcode::kIsub, n, {shifted, d});
  b.op_into(r, 0, Opcode::kSel, {fits, less_d, shifted});
  const Src bit = b.op(Opcode::kAndi, n, {fits}, Imm::integer(1));
  b.op_into(q, 0, Opcode::kOr, {b.op(Opcode::kShli, n, {b.whole(q)}, Imm::integer(1)), bit});
  b.op_into(trips, 0, Opcode::kIaddi, {b.whole(trips)}, Imm::integer(-1));
  b.cond_branch(true, b.whole(trips), top);
  remainder = b.whole(r);
  return b.whole(q);
}

// UDiv, UMod, SDiv, SRem and SMod by a value known only when the shader runs: the
// restoring division on magnitudes, then the signs as for a constant.
Src by_variable(Selection& s) {
  const int n = s.n;
  const auto op = static_cast<Op>(s.op);
  const Src x = s.in.value(0), y = s.in.value(1);
  Src r;
  if (op == Op::OpUDiv || op == Op::OpUMod) {
    const Src q = unsigned_quotient_of(s.b, x, y, n, r);
    return op == Op::OpUDiv ? q : r;
  }
  const Src x_sign = s.b.op(Opcode::kSrai, n, {x}, Imm::integer(31));  // 0 or all ones
  const Src y_sign = s.b.op(Opcode::kSrai, n, {y}, Imm::integer(31));
  const Src x_magnitude = flip_sign(s.b, x, x_sign, n);
  const Src y_magnitude = flip_sign(s.b, y, y_sign, n);
  const Src uq = unsigned_quotient_of(s.b, x_magnitude, y_magnitude, n, r);
  if (op == Op::OpSDiv) return flip_sign(s.b, uq, s.b.op(Opcode::kXor, n, {x_sign, y_sign}), n);
  const Src rem = flip_sign(s.b, r, x_sign, n);  // SRem: |x| mod |y| with x's sign
  return op == Op::OpSRem ? rem : modulo_of_remainder(s.b, rem, y, n);
}

// UDiv, UMod, SDiv, SRem and SMod by a constant. A positive power of two takes shifts and
// masks; any other divisor the magic multiply on magnitudes (signed: the quotient rounds
// toward zero, SRem has the dividend's sign, SMod the divisor's).
Src by_constant(Selection& s) {
  const int n = s.n;
  const auto op = static_cast<Op>(s.op);
  const auto c = s.in.constant(1);
  const bool is_signed = op != Op::OpUDiv && op != Op::OpUMod;
  if (!c) return by_variable(s);
  if (*c == 0) s.b.unsupported(fmt::format("{} by the constant 0", op_name(op)));
  const Src x = s.in.value(0);
  const std::uint32_t d = *c;
  const auto remainder = [&](const Src& q) {
    const Src product = s.b.op(Opcode::kImuli, n, {q}, Imm::bits(d));
    return s.b.op(Opcode::kIsub, n, {x, product});
  };
  if (!is_signed) {
    if (op == Op::OpUMod && std::has_single_bit(d)) return s.b.op(Opcode::kAndi, n, {x}, Imm::bits(d - 1));
    const Src q = unsigned_quotient(s.b, x, d, n);
    return op == Op::OpUDiv ? q : remainder(q);
  }
  const auto sd = static_cast<std::int32_t>(d);
  if (sd > 0 && std::has_single_bit(d)) {
    const int k = std::countr_zero(d);
    // SMod takes the divisor's sign, positive here: the low bits
    if (op == Op::OpSMod) return s.b.op(Opcode::kAndi, n, {x}, Imm::bits(d - 1));
    if (k == 0) return op == Op::OpSDiv ? x : s.b.op(Opcode::kLi, n, {}, Imm::integer(0));  // by 1
    // Round toward zero: add 2^k - 1 to negative x first.
    const Src bias = s.b.op(Opcode::kShri, n, {s.b.op(Opcode::kSrai, n, {x}, Imm::integer(31))}, Imm::integer(32 - k));
    const Src q = s.b.op(Opcode::kSrai, n, {s.b.op(Opcode::kIadd, n, {x, bias})}, Imm::integer(k));
    // SRem: the remainder with x's sign
    return op == Op::OpSDiv ? q : s.b.op(Opcode::kIsub, n, {x, s.b.op(Opcode::kShli, n, {q}, Imm::integer(k))});
  }
  // |x| / |d| unsigned (|INT_MIN| is 2^31), then the quotient's sign: x's, flipped if d < 0.
  const Src sign = s.b.op(Opcode::kSrai, n, {x}, Imm::integer(31));  // 0 or all ones
  const Src magnitude = flip_sign(s.b, x, sign, n);
  const std::uint32_t divisor = sd < 0 ? 0u - d : d;
  const Src uq = unsigned_quotient(s.b, magnitude, divisor, n);
  const Src q_sign = sd < 0 ? s.b.not_of(sign) : sign;
  const Src q = flip_sign(s.b, uq, q_sign, n);
  if (op == Op::OpSDiv) return q;
  const Src r = remainder(q);
  return op == Op::OpSRem ? r : modulo_of_remainder(s.b, r, s.b.op(Opcode::kLi, n, {}, Imm::bits(d)), n);
}

Src uint_to_float(Selection& s) {
  const int n = s.n;
  const Src u = s.in.value(0);
  if (s.in.below_2_31(u)) return s.b.op(Opcode::kI2f, n, {u});  // as a signed integer
  // Values with the top bit set: halve (keeping the low bit sticky), convert, double.
  const Src direct = s.b.op(Opcode::kI2f, n, {u});
  Src half = s.b.op(Opcode::kShri, n, {u}, Imm::integer(1));
  half = s.b.op(Opcode::kOr, n, {half, s.b.op(Opcode::kAndi, n, {u}, Imm::integer(1))});
  Src big = s.b.op(Opcode::kI2f, n, {half});
  big = s.b.op(Opcode::kAdd, n, {big, big});
  return s.b.select(s.b.op(Opcode::kIlti, n, {u}, Imm::integer(0)), big, direct, n);
}

// [0, 2^31) directly, [2^31, 2^32) through f - 2^31; negatives give 0 (f2i saturates).
Src float_to_uint(Selection& s) {
  const int n = s.n;
  const Src f = s.in.value(0);
  const Src two31 = s.b.fconst(2147483648.0f, n);
  const Src low = s.b.op(Opcode::kF2i, n, {s.b.op(Opcode::kMax, n, {f, s.b.fconst(0.0f, n)})});
  Src high = s.b.op(Opcode::kF2i, n, {s.b.op(Opcode::kAdd, n, {f, neg(two31)})});
  high = s.b.op(Opcode::kXori, n, {high}, Imm::bits(0x80000000u));
  return s.b.select(s.b.op(Opcode::kFle, n, {two31, f}), high, low, n);
}

using Expansion = Src (*)(Selection&);

constexpr std::pair<Op, Expansion> kExpandedOps[] = {
    {Op::OpFSub, subtract},
    {Op::OpFDiv, fdiv},
    {Op::OpFNegate, negate},
    {Op::OpFMod, float_mod},
    {Op::OpVectorTimesScalar, vector_times_scalar},
    {Op::OpDot, dot_product},
    {Op::OpMatrixTimesVector, matrix_times_vector},
    {Op::OpVectorTimesMatrix, vector_times_matrix},
    {Op::OpFOrdNotEqual, ord_not_equal},
    {Op::OpFUnordEqual, unord_equal},
    {Op::OpIsNan, is_nan},
    {Op::OpIsInf, is_inf},
    {Op::OpLogicalNot, complement},
    {Op::OpNot, complement},
    {Op::OpAny, any_or_all},
    {Op::OpAll, any_or_all},
    {Op::OpSelect, select_op},
    {Op::OpISub, isub},
    {Op::OpSNegate, snegate},
    {Op::OpUDiv, by_constant},
    {Op::OpUMod, by_constant},
    {Op::OpSDiv, by_constant},
    {Op::OpSMod, by_constant},
    {Op::OpSRem, by_constant},
    {Op::OpConvertUToF, uint_to_float},
    {Op::OpConvertFToU, float_to_uint},
};

// ---- GLSL.std.450 ---------------------------------------------------------------------------

constexpr std::pair<GLSLstd450, Direct> kDirectStd450[] = {
    {GLSLstd450Floor, {Opcode::kFlr}},        {GLSLstd450Fract, {Opcode::kFrc}},
    {GLSLstd450Sqrt, {Opcode::kSqrt}},        {GLSLstd450InverseSqrt, {Opcode::kRsq}},
    {GLSLstd450FMin, {Opcode::kMin}},         {GLSLstd450NMin, {Opcode::kMin}},
    {GLSLstd450FMax, {Opcode::kMax}},         {GLSLstd450NMax, {Opcode::kMax}},
    {GLSLstd450Fma, {Opcode::kMad}},
};

Src absolute(Selection& s) { return abs(s.in.value(0)); }  // a modifier on its uses

Src int_absolute(Selection& s) {
  const int n = s.n;
  const Src x = s.in.value(0);
  // -x before the test, as always
  const Src negated = s.b.op(Opcode::kIsub, n, {s.b.op(Opcode::kLi, n, {}, Imm::integer(0)), x});
  const Src negative = s.b.op(Opcode::kIlti, n, {x}, Imm::integer(0));
  return s.b.select(negative, negated, x, n);
}

Src sign(Selection& s) {
  const int n = s.n;
  const Src x = s.in.value(0);
  const Src pos = s.b.op(Opcode::kFlt, n, {s.b.fconst(0.0f, n), x});
  const Src negative = s.b.op(Opcode::kFlt, n, {x, s.b.fconst(0.0f, n)});
  // 0, -1, their select, then 1, as always
  const Src zero = s.b.fconst(0.0f, n);
  const Src minus_one = s.b.fconst(-1.0f, n);
  const Src not_pos = s.b.select(negative, minus_one, zero, n);
  const Src one = s.b.fconst(1.0f, n);
  return s.b.select(pos, one, not_pos, n);
}

Src ceiling(Selection& s) {
  return s.b.op(Opcode::kMov, s.n, {neg(s.b.op(Opcode::kFlr, s.n, {neg(s.in.value(0))}))});
}

Src truncate(Selection& s) {
  const int n = s.n;
  const Src x = s.in.value(0);
  const Src down = s.b.op(Opcode::kFlr, n, {abs(x)});
  const Src up = s.b.op(Opcode::kMov, n, {neg(down)});  // -down before the test, as always
  const Src negative = s.b.op(Opcode::kFlt, n, {x, s.b.fconst(0.0f, n)});
  return s.b.select(negative, up, down, n);
}

Src round_half_up(Selection& s) {
  return s.b.op(Opcode::kFlr, s.n, {s.b.op(Opcode::kAdd, s.n, {s.in.value(0), s.b.fconst(0.5f, s.n)})});
}

Src clamp(Selection& s) {
  return s.b.op(Opcode::kMin, s.n, {s.b.op(Opcode::kMax, s.n, {s.in.value(0), s.in.value(1)}), s.in.value(2)});
}

// SMin, SMax, UMin, UMax: a compare and a select.
Src integer_min_max(Selection& s) {
  const int n = s.n;
  const Src x = s.in.value(0), y = s.in.value(1);
  const bool u = s.op == GLSLstd450UMin || s.op == GLSLstd450UMax;
  const Src lt = s.b.op(u ? Opcode::kIltu : Opcode::kIlt, n, {x, y});
  const bool min = s.op == GLSLstd450SMin || s.op == GLSLstd450UMin;
  return s.b.select(lt, min ? x : y, min ? y : x, n);
}

Src integer_clamp(Selection& s) {
  const int n = s.n;
  const Opcode less = s.op == GLSLstd450UClamp ? Opcode::kIltu : Opcode::kIlt;
  const Src x = s.in.value(0), lo = s.in.value(1), hi = s.in.value(2);
  const Src a = s.b.select(s.b.op(less, n, {x, lo}), lo, x, n);
  return s.b.select(s.b.op(less, n, {hi, a}), hi, a, n);
}

// x + (y - x) a
Src mix(Selection& s) {
  const Src x = s.in.value(0), y = s.in.value(1), a = s.in.value(2);
  return s.b.op(Opcode::kMad, s.n, {s.b.op(Opcode::kAdd, s.n, {y, neg(x)}), a, x});
}

Src step(Selection& s) {
  const int n = s.n;
  const Src edge = s.in.value(0), x = s.in.value(1);
  // 1, 0, then the test, as always
  const Src one = s.b.fconst(1.0f, n);
  const Src zero = s.b.fconst(0.0f, n);
  const Src below = s.b.op(Opcode::kFlt, n, {x, edge});
  return s.b.select(below, zero, one, n);
}

// t = clamp((x - e0) / (e1 - e0), 0, 1); t^2 (3 - 2t)
Src smoothstep(Selection& s) {
  const int n = s.n;
  const Src e0 = s.in.value(0), e1 = s.in.value(1), x = s.in.value(2);
  const Src range = s.b.op(Opcode::kAdd, n, {e1, neg(e0)});  // e1 - e0 before x - e0, as always
  Src t = divide(s.b, s.b.op(Opcode::kAdd, n, {x, neg(e0)}), range, n);
  t = s.b.op(Opcode::kMin, n, {s.b.op(Opcode::kMax, n, {t, s.b.fconst(0.0f, n)}), s.b.fconst(1.0f, n)});
  const Src k = s.b.op(Opcode::kMad, n, {t, s.b.fconst(-2.0f, n), s.b.fconst(3.0f, n)});
  return s.b.op(Opcode::kMul, n, {s.b.op(Opcode::kMul, n, {t, t}), k});
}

Src sine_of(Selection& s) { return sine(s.b, s.in.value(0), s.n); }

Src cosine_of(Selection& s) {
  return sine(s.b, s.b.op(Opcode::kAdd, s.n, {s.in.value(0), s.b.fconst(1.57079632679f, s.n)}), s.n);
}

Src tangent_of(Selection& s) { return tangent(s.b, s.in.value(0), s.n); }

Src arctangent_of(Selection& s) {
  const Src y = s.in.value(0);
  const Src one = s.b.fconst(1.0f, s.n);
  return arctangent2(s.b, y, one, s.n);
}

Src arctangent2_of(Selection& s) {
  const Src y = s.in.value(0), x = s.in.value(1);
  return arctangent2(s.b, y, x, s.n);
}

// sqrt(1 - x^2) as sqrt((1 - x)(1 + x)), exact near |x| = 1 where 1 - x^2 cancels.
Src cosine_of_arcsine(Selection& s, const Src& x) {
  const Src one = s.b.fconst(1.0f, s.n);
  const Src left = s.b.op(Opcode::kAdd, s.n, {one, neg(x)});
  const Src right = s.b.op(Opcode::kAdd, s.n, {one, x});
  return s.b.op(Opcode::kSqrt, s.n, {s.b.op(Opcode::kMul, s.n, {left, right})});
}

Src arcsine_of(Selection& s) {
  const Src x = s.in.value(0);
  return arctangent2(s.b, x, cosine_of_arcsine(s, x), s.n);
}

Src arccosine_of(Selection& s) {
  const Src x = s.in.value(0);
  return arctangent2(s.b, cosine_of_arcsine(s, x), x, s.n);
}

Src exp2_of(Selection& s) { return exp2(s.b, s.in.value(0), s.n); }

Src log2_of(Selection& s) { return log2(s.b, s.in.value(0), s.n); }

Src exp_of(Selection& s) {
  return exp2(s.b, s.b.op(Opcode::kMul, s.n, {s.in.value(0), s.b.fconst(1.44269504f, s.n)}), s.n);
}

Src log_of(Selection& s) {
  return s.b.op(Opcode::kMul, s.n, {log2(s.b, s.in.value(0), s.n), s.b.fconst(0.693147181f, s.n)});
}

Src power(Selection& s) {
  return exp2(s.b, s.b.op(Opcode::kMul, s.n, {log2(s.b, s.in.value(0), s.n), s.in.value(1)}), s.n);
}

Src length(Selection& s) {
  const Src v = s.in.value(0);
  return v.n == 1 ? s.b.op(Opcode::kMov, 1, {abs(v)}) : s.b.op(Opcode::kSqrt, 1, {dot(s.b, v, v)});
}

Src distance(Selection& s) {
  const Src x = s.in.value(0), y = s.in.value(1);
  const Src d = s.b.op(Opcode::kAdd, x.n, {x, neg(y)});
  return d.n == 1 ? s.b.op(Opcode::kMov, 1, {abs(d)}) : s.b.op(Opcode::kSqrt, 1, {dot(s.b, d, d)});
}

Src normalize(Selection& s) {
  const Src v = s.in.value(0);
  const Src r = s.b.op(Opcode::kRsq, 1, {dot(s.b, v, v)});
  return s.b.op(Opcode::kMul, s.n, {v, broadcast(r, s.n)});
}

// x.yzx y.zxy - x.zxy y.yzx, as one mul and one mad
Src cross(Selection& s) {
  const Src x = s.in.value(0), y = s.in.value(1);
  const auto perm = [](Src v, std::uint8_t i, std::uint8_t j, std::uint8_t k) {
    const auto c = v.comp;
    v.comp = {c[i], c[j], c[k], c[i]};
    v.n = 3;
    return v;
  };
  const Src t = s.b.op(Opcode::kMul, 3, {perm(x, 2, 0, 1), perm(y, 1, 2, 0)});
  return s.b.op(Opcode::kMad, 3, {perm(x, 1, 2, 0), perm(y, 2, 0, 1), neg(t)});
}

// I - 2 dot(N, I) N
Src reflect(Selection& s) {
  const Src in = s.in.value(0), nrm = s.in.value(1);
  Src d = dot(s.b, nrm, in);
  d = s.b.op(Opcode::kAdd, 1, {d, d});
  return s.b.op(Opcode::kMad, s.n, {nrm, broadcast(neg(d), s.n), in});
}

// k = 1 - eta^2 (1 - dot(N,I)^2); k < 0 ? 0 : eta I - (eta dot(N,I) + sqrt(k)) N
Src refract(Selection& s) {
  const int n = s.n;
  const Src in = s.in.value(0), nrm = s.in.value(1), eta = s.in.value(2);
  const Src d = dot(s.b, nrm, in);
  const Src one = s.b.fconst(1.0f);
  Src k = s.b.op(Opcode::kMad, 1, {neg(d), d, one});
  k = s.b.op(Opcode::kMul, 1, {s.b.op(Opcode::kMul, 1, {eta, eta}), k});
  k = s.b.op(Opcode::kAdd, 1, {one, neg(k)});
  const Src q = s.b.op(Opcode::kMad, 1,
                       {eta, d, s.b.op(Opcode::kSqrt, 1, {s.b.op(Opcode::kMax, 1, {k, s.b.fconst(0.0f)})})});
  const Src r = s.b.op(Opcode::kMad, n, {broadcast(eta, n), in, s.b.op(Opcode::kMul, n, {nrm, broadcast(neg(q), n)})});
  const Src zero = s.b.fconst(0.0f, n);  // the 0 before the test, as always
  const Src total_reflection = s.b.op(Opcode::kFlt, 1, {k, s.b.fconst(0.0f)});
  return s.b.select(total_reflection, zero, r, n);
}

// dot(Nref, I) < 0 ? N : -N
Src faceforward(Selection& s) {
  const Src nn = s.in.value(0), in = s.in.value(1), nref = s.in.value(2);
  const Src flipped = s.b.op(Opcode::kMov, s.n, {neg(nn)});  // -N before the test, as always
  const Src facing = s.b.op(Opcode::kFlt, 1, {dot(s.b, nref, in), s.b.fconst(0.0f)});
  return s.b.select(facing, nn, flipped, s.n);
}

constexpr std::pair<GLSLstd450, Expansion> kExpandedStd450[] = {
    {GLSLstd450FAbs, absolute},
    {GLSLstd450SAbs, int_absolute},
    {GLSLstd450FSign, sign},
    {GLSLstd450Ceil, ceiling},
    {GLSLstd450Trunc, truncate},
    {GLSLstd450Round, round_half_up},
    {GLSLstd450FClamp, clamp},
    {GLSLstd450NClamp, clamp},
    {GLSLstd450SMin, integer_min_max},
    {GLSLstd450SMax, integer_min_max},
    {GLSLstd450UMin, integer_min_max},
    {GLSLstd450UMax, integer_min_max},
    {GLSLstd450SClamp, integer_clamp},
    {GLSLstd450UClamp, integer_clamp},
    {GLSLstd450FMix, mix},
    {GLSLstd450Step, step},
    {GLSLstd450SmoothStep, smoothstep},
    {GLSLstd450Sin, sine_of},
    {GLSLstd450Cos, cosine_of},
    {GLSLstd450Tan, tangent_of},
    {GLSLstd450Atan, arctangent_of},
    {GLSLstd450Atan2, arctangent2_of},
    {GLSLstd450Asin, arcsine_of},
    {GLSLstd450Acos, arccosine_of},
    {GLSLstd450Exp2, exp2_of},
    {GLSLstd450Log2, log2_of},
    {GLSLstd450Exp, exp_of},
    {GLSLstd450Log, log_of},
    {GLSLstd450Pow, power},
    {GLSLstd450Length, length},
    {GLSLstd450Distance, distance},
    {GLSLstd450Normalize, normalize},
    {GLSLstd450Cross, cross},
    {GLSLstd450Reflect, reflect},
    {GLSLstd450Refract, refract},
    {GLSLstd450FaceForward, faceforward},
};

// The row of `table` for `key`, or null.
template <class Key, class Value, std::size_t N>
const Value* find(const std::pair<Key, Value> (&table)[N], Key key) {
  for (const auto& [k, v] : table) {
    if (k == key) return &v;
  }
  return nullptr;
}

}  // namespace

std::optional<Src> select(Builder& b, spv::Op op, int width, Operands& operands) {
  Selection s{b, operands, width, static_cast<std::uint32_t>(op)};
  if (const Direct* d = find(kDirectOps, op)) return direct(s, *d);
  if (const Expansion* e = find(kExpandedOps, op)) return (*e)(s);
  return std::nullopt;
}

Src select_glsl_std_450(Builder& b, std::uint32_t instruction, int width, Operands& operands) {
  Selection s{b, operands, width, instruction};
  const auto key = static_cast<GLSLstd450>(instruction);
  if (const Direct* d = find(kDirectStd450, key)) return direct(s, *d);
  if (const Expansion* e = find(kExpandedStd450, key)) return (*e)(s);
  b.unsupported(fmt::format("{}() (GLSL.std.450 {})", glsl_std_450_function(instruction),
                            glsl_std_450_name(instruction)));
}

}  // namespace rpu::cc
