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
