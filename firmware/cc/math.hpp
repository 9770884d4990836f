// The math library: GLSL functions the RPU has no instruction for, as instruction
// sequences over n lanes (docs/shaders.md "What compiles" states their accuracy).
#pragma once

#include "cc/builder.hpp"

namespace rpu::cc {

// x . y of 1 to 4 components, into one lane: dp3 and dp4 where they fit.
Src dot(Builder& b, const Src& x, const Src& y);
// x / y as x * (1/y), with the correctly rounded reciprocal.
Src divide(Builder& b, const Src& x, const Src& y, int n);
// 2^y, as firmware/whitted.s's pow computes it.
Src exp2(Builder& b, const Src& y, int n);
// log2 x for x > 0, as firmware/whitted.s's pow computes it.
Src log2(Builder& b, const Src& x, int n);
// sin x; cos x is sin(x + pi/2).
Src sine(Builder& b, const Src& x, int n);
// tan x, from x reduced to [-pi/4, pi/4] (Cephes' tanf).
Src tangent(Builder& b, const Src& x, int n);
// atan2(y, x), the angle of (x, y) in [-pi, pi]: 0 for (0, 0). atan y is atan2(y, 1),
// asin and acos atan2 of x and sqrt(1 - x^2).
Src arctangent2(Builder& b, const Src& y, const Src& x, int n);

}  // namespace rpu::cc
