#include "cc/math.hpp"

#include <iterator>

namespace rpu::cc {

Src dot(Builder& b, const Src& x, const Src& y) {
  if (x.n == 3) return b.op(Opcode::kDp3, 1, {x, y});
  if (x.n == 4) return b.op(Opcode::kDp4, 1, {x, y});
  if (x.n == 1) return b.op(Opcode::kMul, 1, {x, y});
  const Src p = b.op(Opcode::kMul, 2, {x, y});
  return b.op(Opcode::kAdd, 1, {component(p, 0), component(p, 1)});
}

Src divide(Builder& b, const Src& x, const Src& y, int n) {
  const Src r = b.op(Opcode::kRcp, y.n, {y});
  return b.op(Opcode::kMul, n, {x, r});
}

// exp2 as firmware/whitted.s's pow computes it: 2^i 2^(g) sqrt(2) with g = y - i - 1/2,
// the Taylor series of 2^g to g^6 (relative error < 2e-7); y clamped to [-126, 128].
Src exp2(Builder& b, const Src& y_in, int n) {
  Src y = b.op(Opcode::kMax, n, {y_in, b.fconst(-126.0f, n)});
  y = b.op(Opcode::kMin, n, {y, b.fconst(128.0f, n)});
  const Src i = b.op(Opcode::kFlr, n, {y});
  Src g = b.op(Opcode::kAdd, n, {y, neg(i)});
  g = b.op(Opcode::kAdd, n, {g, neg(b.fconst(0.5f, n))});
  static constexpr float kCoefficients[] = {0.00015403530393381606f, 0.0013333558146428443f, 0.009618129107628477f,
                                            0.05550410866482158f,    0.2402265069591007f,    0.6931471805599453f,
                                            1.0f};
  Src p = b.fconst(kCoefficients[0], n);
  for (std::size_t k = 1; k < std::size(kCoefficients); ++k) {
    p = b.op(Opcode::kMad, n, {p, g, b.fconst(kCoefficients[k], n)});
  }
  Src e = b.op(Opcode::kF2i, n, {i});
  e = b.op(Opcode::kIaddi, n, {e}, Imm::integer(127));
  e = b.op(Opcode::kShli, n, {e}, Imm::integer(23));  // 2^i as fp32 bits
  p = b.op(Opcode::kMul, n, {p, e});
  return b.op(Opcode::kMul, n, {p, b.fconst(1.41421356f, n)});
}

// sin: x reduced to y in [-pi, pi) through the fraction of x / 2pi, then the Taylor
// series to y^17 (absolute error below 3e-8 on the interval, plus the reduction's
// rounding, which grows with |x|).
Src sine(Builder& b, const Src& x, int n) {
  Src f = b.op(Opcode::kMad, n, {x, b.fconst(0.159154943f, n), b.fconst(0.5f, n)});  // x / 2pi + 1/2
  f = b.op(Opcode::kFrc, n, {f});
  const Src y = b.op(Opcode::kMul, n, {b.op(Opcode::kAdd, n, {f, neg(b.fconst(0.5f, n))}), b.fconst(6.28318531f, n)});
  const Src y2 = b.op(Opcode::kMul, n, {y, y});
  // sin y = y (1 - y^2/3! (1 - y^2/(4 5) (1 - ...))): Horner in y^2 with 1/k! coefficients
  static constexpr float kCoefficients[] = {2.81145725e-15f, -7.64716373e-13f, 1.60590438e-10f, -2.50521084e-8f,
                                            2.75573192e-6f,  -1.98412698e-4f,  8.33333333e-3f,  -1.66666667e-1f,
                                            1.0f};
  Src p = b.fconst(kCoefficients[0], n);
  for (std::size_t k = 1; k < std::size(kCoefficients); ++k) {
    p = b.op(Opcode::kMad, n, {p, y2, b.fconst(kCoefficients[k], n)});
  }
  return b.op(Opcode::kMul, n, {p, y});
}

// tan as Cephes' tanf: |x| less j pi/4 for the even j nearest (x 4/pi), pi/4 in three
// parts so that j pi/4 is subtracted nearly exactly, then a polynomial on [-pi/4, pi/4];
// where j/2 is odd, tan is -1/that; the sign of x last (relative error about 2e-7 while
// j pi/4 stays exact, |x| below some thousands).
Src tangent(Builder& b, const Src& x, int n) {
  const Src j_low = b.op(Opcode::kFlr, n, {b.op(Opcode::kMul, n, {abs(x), b.fconst(1.27323954f, n)})});
  const Src odd = b.op(Opcode::kFrc, n, {b.op(Opcode::kMul, n, {j_low, b.fconst(0.5f, n)})});  // 0 or 1/2
  const Src j = b.op(Opcode::kMad, n, {odd, b.fconst(2.0f, n), j_low});
  Src z = b.op(Opcode::kMad, n, {neg(j), b.fconst(0.78515625f, n), abs(x)});
  z = b.op(Opcode::kMad, n, {neg(j), b.fconst(2.4187564849853515625e-4f, n), z});
  z = b.op(Opcode::kMad, n, {neg(j), b.fconst(3.77489497744594108e-8f, n), z});
  const Src zz = b.op(Opcode::kMul, n, {z, z});
  static constexpr float kCoefficients[] = {9.38540185543e-3f, 3.11992232697e-3f, 2.44301354525e-2f,
                                            5.34112807005e-2f, 1.33387994085e-1f, 3.33331568548e-1f};
  Src p = b.fconst(kCoefficients[0], n);
  for (std::size_t k = 1; k < std::size(kCoefficients); ++k) {
    p = b.op(Opcode::kMad, n, {p, zz, b.fconst(kCoefficients[k], n)});
  }
  p = b.op(Opcode::kMul, n, {p, zz});
  p = b.op(Opcode::kMad, n, {p, z, z});
  const Src quarter = b.op(Opcode::kFrc, n, {b.op(Opcode::kMul, n, {j, b.fconst(0.25f, n)})});  // 0 or 1/2
  const Src cotangent = b.op(Opcode::kFne, n, {quarter, b.fconst(0.0f, n)});
  const Src inverse = b.op(Opcode::kRcp, n, {p});
  const Src t = b.select(cotangent, neg(inverse), p, n);
  const Src negative = b.op(Opcode::kFlt, n, {x, b.fconst(0.0f, n)});
  return b.select(negative, neg(t), t, n);
}

// atan t for t in [0, 1]: t above tan(pi/8) is moved below it by atan t = pi/4 +
// atan((t - 1) / (t + 1)), then Cephes' atanf polynomial in t^2 (relative error below
// 2e-7 on [0, tan(pi/8)]).
Src arctangent_unit(Builder& b, const Src& t, int n) {
  const Src one = b.fconst(1.0f, n);
  const Src high = b.op(Opcode::kFlt, n, {b.fconst(0.414213562f, n), t});
  const Src below = b.op(Opcode::kAdd, n, {t, neg(one)});
  const Src above = b.op(Opcode::kRcp, n, {b.op(Opcode::kAdd, n, {t, one})});
  const Src moved = b.op(Opcode::kMul, n, {below, above});
  const Src u = b.select(high, moved, t, n);
  const Src z = b.op(Opcode::kMul, n, {u, u});
  static constexpr float kCoefficients[] = {8.05374449538e-2f, -1.38776856032e-1f, 1.99777106478e-1f,
                                            -3.33329491539e-1f};
  Src p = b.fconst(kCoefficients[0], n);
  for (std::size_t k = 1; k < std::size(kCoefficients); ++k) {
    p = b.op(Opcode::kMad, n, {p, z, b.fconst(kCoefficients[k], n)});
  }
  p = b.op(Opcode::kMul, n, {p, z});
  p = b.op(Opcode::kMad, n, {p, u, u});
  const Src shifted = b.op(Opcode::kAdd, n, {p, b.fconst(0.785398163f, n)});
  return b.select(high, shifted, p, n);
}

// The smaller of |x| and |y| over the larger gives the angle within an octant; the
// octant's reflections (|y| > |x|: pi/2 - a; x < 0: pi - a; y < 0: -a) give the rest.
Src arctangent2(Builder& b, const Src& y, const Src& x, int n) {
  const Src zero = b.fconst(0.0f, n);
  const Src larger = b.op(Opcode::kMax, n, {abs(x), abs(y)});
  const Src smaller = b.op(Opcode::kMin, n, {abs(x), abs(y)});
  const Src ratio = b.op(Opcode::kMul, n, {smaller, b.op(Opcode::kRcp, n, {larger})});
  const Src origin = b.op(Opcode::kFeq, n, {larger, zero});
  const Src t = b.select(origin, zero, ratio, n);
  Src a = arctangent_unit(b, t, n);
  const Src steep = b.op(Opcode::kFlt, n, {abs(x), abs(y)});
  const Src from_half_pi = b.op(Opcode::kAdd, n, {b.fconst(1.57079633f, n), neg(a)});
  a = b.select(steep, from_half_pi, a, n);
  const Src left = b.op(Opcode::kFlt, n, {x, zero});
  const Src from_pi = b.op(Opcode::kAdd, n, {b.fconst(3.14159265f, n), neg(a)});
  a = b.select(left, from_pi, a, n);
  const Src below = b.op(Opcode::kFlt, n, {y, zero});
  return b.select(below, neg(a), a, n);
}

// log2 as firmware/whitted.s's pow computes it: x = m 2^e with m in [sqrt(1/2), sqrt(2)),
// log2 m = (2/ln 2) atanh((m-1)/(m+1)) to t^9. For x > 0; 0 gives -126.something, so
// exp2 of a product with it still flushes to 0.
Src log2(Builder& b, const Src& x, int n) {
  Src e = b.op(Opcode::kShri, n, {x}, Imm::integer(23));
  e = b.op(Opcode::kIaddi, n, {e}, Imm::integer(-127));
  Src m = b.op(Opcode::kAndi, n, {x}, Imm::bits(0x007fffffu));
  m = b.op(Opcode::kOri, n, {m}, Imm::bits(0x3f800000u));
  const Src big = b.op(Opcode::kFle, n, {b.fconst(1.41421356f, n), m});
  m = b.select(big, b.op(Opcode::kMul, n, {m, b.fconst(0.5f, n)}), m, n);
  e = b.select(big, b.op(Opcode::kIaddi, n, {e}, Imm::integer(1)), e, n);
  const Src ef = b.op(Opcode::kI2f, n, {e});
  const Src one = b.fconst(1.0f, n);
  Src t = b.op(Opcode::kAdd, n, {m, neg(one)});
  t = b.op(Opcode::kMul, n, {t, b.op(Opcode::kRcp, n, {b.op(Opcode::kAdd, n, {m, one})})});
  const Src t2 = b.op(Opcode::kMul, n, {t, t});
  static constexpr float kCoefficients[] = {0.3205988979753252f, 0.41219858311113244f, 0.5770780163555854f,
                                            0.9617966939259756f, 2.8853900817779268f};
  Src p = b.fconst(kCoefficients[0], n);
  for (std::size_t k = 1; k < std::size(kCoefficients); ++k) {
    p = b.op(Opcode::kMad, n, {p, t2, b.fconst(kCoefficients[k], n)});
  }
  p = b.op(Opcode::kMul, n, {p, t});
  return b.op(Opcode::kAdd, n, {ef, p});
}

}  // namespace rpu::cc
