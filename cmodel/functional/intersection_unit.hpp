#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <utility>

#include "fp/format.hpp"
#include "functional/trace_types.hpp"
#include "rpu/spec.hpp"
#include "rpu/streams.hpp"

namespace rpu::functional {

// A triangle's intersection record as the IU reads it from the image: three float4 rows
// (Woop) or vertices (watertight) at the [triangle_record] offsets of
// spec/memory_map.toml, IsectRecordWords words (spec/streams.toml) in either variant.
using IsectRecord = std::array<std::uint32_t, streams::kIsectRecordWords>;
// The word where row k (Woop) or vertex k (watertight) starts; its w is 3 words on.
inline constexpr std::array<int, 3> kRecordRow{static_cast<int>(spec::memory::kTriangleRecordRow0At / 4),
                                               static_cast<int>(spec::memory::kTriangleRecordRow1At / 4),
                                               static_cast<int>(spec::memory::kTriangleRecordRow2At / 4)};
static_assert(kRecordRow[0] + 4 <= int{streams::kIsectRecordWords} &&
              kRecordRow[1] + 4 <= int{streams::kIsectRecordWords} &&
              kRecordRow[2] + 4 <= int{streams::kIsectRecordWords});

// The intersection unit's two tests, on records read from the memory image and a ray in
// the unit's format (docs/traversal.md §4 and §5 give every operation in order; the RTL
// implements the same sequence). Each returns whether the triangle is hit strictly
// inside (t_min, t_best) and then sets t, u, v. Every product and sum is rounded
// separately: no fused multiply-add. Both are inlined into the walk: as calls they cost
// 7% of a fast-path ray's instructions (callgrind, docs/perf.md).

template <class Arith>
struct RayRegisters {
  using V = typename Arith::Value;
  std::array<V, 3> origin, direction, inv_direction;
  V t_min, t_max;
  // Watertight test (Woop, Benthin, Wald 2013, §3): the dominant axis kz, the other two
  // axes kx, ky (swapped when direction[kz] < 0 to keep the winding) and the shear.
  int kx = 0, ky = 1, kz = 2;
  V shear_x, shear_y;
};

// §1 Ray set-up: moves the ray into kd space (origin and interval times 2^-kd_scale,
// exact in fp32: the image's geometry is world space times 2^-kd_scale), rounds it into
// the format, and for the watertight test picks the axes and the shear. Returns false
// for a defined miss (a NaN or infinite component, a zero direction or an empty
// interval), which fetches nothing.
template <class Arith>
bool setup_ray(const Arith& ar, const TraceRay& in, bool watertight, int kd_scale, RayRegisters<Arith>& ray) {
  using V = typename Arith::Value;
  const auto to_kd = [&](float x) { return ar.load(fp::scale_fp32(std::bit_cast<std::uint32_t>(x), -kd_scale)); };
  bool valid = true;
  bool zero_direction = true;
  const V infinity = ar.load(0x7f800000u);
  for (int i = 0; i < 3; ++i) {
    ray.origin[i] = to_kd(in.origin[i]);
    ray.direction[i] = ar.load(std::bit_cast<std::uint32_t>(in.direction[i]));
    valid = valid && ar.lt(ar.abs(ray.origin[i]), infinity) && ar.lt(ar.abs(ray.direction[i]), infinity);
    zero_direction = zero_direction && ar.eq(ray.direction[i], ar.zero());
  }
  ray.t_min = to_kd(in.t_min);
  ray.t_max = to_kd(in.t_max);
  if (!valid || zero_direction || !ar.lt(ray.t_min, ray.t_max)) return false;
  for (int i = 0; i < 3; ++i) ray.inv_direction[i] = ar.rcp(ray.direction[i]);
  if (watertight) {
    const V ax = ar.abs(ray.direction[0]), ay = ar.abs(ray.direction[1]), az = ar.abs(ray.direction[2]);
    ray.kz = ar.le(ay, ax) && ar.le(az, ax) ? 0 : (ar.le(az, ay) ? 1 : 2);
    ray.kx = (ray.kz + 1) % 3;
    ray.ky = (ray.kx + 1) % 3;
    if (ar.lt(ray.direction[ray.kz], ar.zero())) std::swap(ray.kx, ray.ky);
    ray.shear_x = ar.div(ray.direction[ray.kx], ray.direction[ray.kz]);
    ray.shear_y = ar.div(ray.direction[ray.ky], ray.direction[ray.kz]);
  }
  return true;
}

template <class Arith>
struct UnitHit {
  typename Arith::Value t, u, v;
};

// dp3(a, b) = (a0*b0 + a1*b1) + a2*b2.
template <class Arith, class V = typename Arith::Value>
V dot3(const Arith& ar, V a0, V a1, V a2, const std::array<V, 3>& b) {
  return ar.add(ar.add(ar.mul(a0, b[0]), ar.mul(a1, b[1])), ar.mul(a2, b[2]));
}

// Woop's unit-triangle test (Woop, Schmittler, Slusallek 2005, §4.2). The record's rows
// r0, r1, r2 map world space to the triangle's unit space, (u, v, w) = L (p - A): their
// xyz hold the linear part L, their w the vertex A (docs/memory-map.md). Measuring from
// A rather than adding a stored translation -L A keeps t accurate relative to t: the
// translation, rounded, would misplace the plane by an ulp of the scene's coordinates.
template <class Arith>
[[gnu::always_inline]] inline bool intersect_woop(const Arith& ar, const RayRegisters<Arith>& ray, const IsectRecord& record,
                    typename Arith::Value t_best, UnitHit<Arith>& out) {
  using V = typename Arith::Value;
  constexpr int r0 = kRecordRow[0], r1 = kRecordRow[1], r2 = kRecordRow[2];
  // Rows are loaded as the test needs them: most tests end after row 2.
  std::array<V, streams::kIsectRecordWords> m;
  for (const int i : {r0 + 3, r1 + 3, r2 + 3, r2, r2 + 1, r2 + 2}) m[i] = ar.load(record[i]);
  const std::array<V, 3> p{ar.sub(ray.origin[0], m[r0 + 3]), ar.sub(ray.origin[1], m[r1 + 3]),
                           ar.sub(ray.origin[2], m[r2 + 3])};
  const V oz = dot3(ar, m[r2], m[r2 + 1], m[r2 + 2], p);
  const V dz = dot3(ar, m[r2], m[r2 + 1], m[r2 + 2], ray.direction);
  const V t = ar.neg(ar.div(oz, dz));
  if (!(ar.gt(t, ray.t_min) && ar.lt(t, t_best))) return false;
  for (const int i : {r0, r0 + 1, r0 + 2, r1, r1 + 1, r1 + 2}) m[i] = ar.load(record[i]);
  const V ox = dot3(ar, m[r0], m[r0 + 1], m[r0 + 2], p);
  const V dx = dot3(ar, m[r0], m[r0 + 1], m[r0 + 2], ray.direction);
  const V u = ar.add(ox, ar.mul(t, dx));
  if (!(ar.le(ar.zero(), u) && ar.le(u, ar.one()))) return false;
  const V oy = dot3(ar, m[r1], m[r1 + 1], m[r1 + 2], p);
  const V dy = dot3(ar, m[r1], m[r1 + 1], m[r1 + 2], ray.direction);
  const V v = ar.add(oy, ar.mul(t, dy));
  if (!(ar.le(ar.zero(), v) && ar.le(ar.add(u, v), ar.one()))) return false;
  out = {t, u, v};
  return true;
}

// The watertight test (Woop, Benthin, Wald 2013, Fig. 5, without the double-precision
// fallback: edge functions are each one rounded difference of two rounded products, so
// an edge shared by two triangles gets exactly opposite values in both and no ray
// slips between them). The record holds the vertices A, B, C as float4 with the unit
// normal n in their w components. The paper's t, a sum of edge functions times sheared
// vertex distances, loses the digits of t when the vertices lie far from the hit on both
// sides of the origin, and is cubic in the coordinates; t = n.(A - O) / n.D, as Embree
// computes it, is a distance from the plane, accurate relative to t and linear in the
// coordinates (docs/traversal.md §5).
template <class Arith>
[[gnu::always_inline]] inline bool intersect_watertight(const Arith& ar, const RayRegisters<Arith>& ray,
                          const IsectRecord& record, typename Arith::Value t_best,
                          UnitHit<Arith>& out) {
  using V = typename Arith::Value;
  std::array<std::array<V, 3>, 3> p;  // A, B, C relative to the origin
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) p[k][i] = ar.sub(ar.load(record[kRecordRow[k] + i]), ray.origin[i]);
  }
  std::array<V, 3> x, y;
  for (int k = 0; k < 3; ++k) {
    x[k] = ar.sub(p[k][ray.kx], ar.mul(ray.shear_x, p[k][ray.kz]));
    y[k] = ar.sub(p[k][ray.ky], ar.mul(ray.shear_y, p[k][ray.kz]));
  }
  // Edge functions: U for edge BC (weight of A), V for CA (B), W for AB (C).
  const V eu = ar.sub(ar.mul(x[2], y[1]), ar.mul(y[2], x[1]));
  const V ev = ar.sub(ar.mul(x[0], y[2]), ar.mul(y[0], x[2]));
  const V ew = ar.sub(ar.mul(x[1], y[0]), ar.mul(y[1], x[0]));
  const V zero = ar.zero();
  const bool any_negative = ar.lt(eu, zero) || ar.lt(ev, zero) || ar.lt(ew, zero);
  const bool any_positive = ar.gt(eu, zero) || ar.gt(ev, zero) || ar.gt(ew, zero);
  if (any_negative && any_positive) return false;
  const V det = ar.add(ar.add(eu, ev), ew);
  if (!(ar.lt(det, zero) || ar.gt(det, zero))) return false;  // zero or NaN
  const V n0 = ar.load(record[kRecordRow[0] + 3]), n1 = ar.load(record[kRecordRow[1] + 3]),
          n2 = ar.load(record[kRecordRow[2] + 3]);
  const V t = ar.div(dot3(ar, n0, n1, n2, p[0]), dot3(ar, n0, n1, n2, ray.direction));
  if (!(ar.gt(t, ray.t_min) && ar.lt(t, t_best))) return false;
  out = {t, ar.div(ev, det), ar.div(ew, det)};
  return true;
}

}  // namespace rpu::functional
