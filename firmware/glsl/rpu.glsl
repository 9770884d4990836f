// The RPU shader interface (docs/shaders.md). A shader starts
//   #version 460
//   #extension GL_EXT_ray_tracing : require
//   #include "rpu.glsl"
// and gets the scene's buffers and records (rpu_memory.glsl, generated from
// spec/memory_map.toml and spec/shaders.toml), the framebuffer, the acceleration
// structure, and the random stream of docs/shading.md section 1.
#ifndef RPU_GLSL
#define RPU_GLSL

#include "rpu_memory.glsl"

// +infinity: t_max of a ray that goes on for ever.
#define RPU_INFINITY uintBitsToFloat(0x7f800000u)

// PCG RXS-M-XS 32/32 (O'Neill 2014): the output permutation, the hash
// h(x) = perm(x * 747796405 + 2891336453), and one draw, which returns perm(state) as
// a float in [0, 1) (its top 23 bits as the fraction) and steps the state.
uint rpu_permute(uint x) {
  uint w = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  return (w >> 22u) ^ w;
}

uint rpu_hash(uint x) { return rpu_permute(x * 747796405u + 2891336453u); }

float rpu_random(inout uint state) {
  uint old = state;
  state = state * 747796405u + 2891336453u;
  return uintBitsToFloat((rpu_permute(old) >> 9u) | 0x3f800000u) - 1.0;
}

// The stream of one sample: h(seed ^ h(pixel ^ h(sample))).
uint rpu_sample_stream(uint pixel, uint sample_index) {
  return rpu_hash(launch_record.seed ^ rpu_hash(pixel ^ rpu_hash(sample_index)));
}

// 2^e, the power of two of x's binade (x = m 2^e, m in [1, 2)), and 2^-e: exact, from
// x's exponent bits, without the sfu (rcp takes it a thread at a time). Scaling a vector
// by rpu_binade_down of its largest component brings that into [1, 2), so that its
// squared length neither overflows nor flushes in a narrow format. For finite x > 0.
float rpu_binade(float x) { return uintBitsToFloat(floatBitsToUint(x) & 0x7f800000u); }
float rpu_binade_down(float x) { return uintBitsToFloat(0x7f000000u - (floatBitsToUint(x) & 0x7f800000u)); }

// p, a point of a surface, moved off it along the unit normal n, robustly in the chip's
// number format: `outside` the origin of a ray that leaves p on n's side, `inside` on the
// other (docs/shading.md "Leaving a surface"). Each coordinate moves RPU_RAY_OFFSET_ULPS
// of the format's ulps there times n's component, an integer add on its bits (one ulp of
// the format is bit 23 - M of the fp32 pattern); a coordinate under
// ray_epsilon x 2^M / RPU_RAY_OFFSET_ULPS, where that would move it less, moves by
// ray_epsilon times the component.
void rpu_offset_rays(vec3 p, vec3 n, out vec3 outside, out vec3 inside) {
  const int shift = int(scene_record.ray_offset_shift);
  const float eps = scene_record.ray_epsilon;
  // |p| < eps 2^M / ulps as |p| ulps < eps 2^M: 2^M from its exponent bits, no division
  const float two_to_m = uintBitsToFloat(uint(150 - shift) << 23);
  const bvec3 small = lessThan(abs(p) * float(RPU_RAY_OFFSET_ULPS), vec3(two_to_m * eps));
  const ivec3 steps = ivec3(n * float(RPU_RAY_OFFSET_ULPS)) << shift;
  // where p < 0 (its sign bit set) a step up the bit pattern moves it down
  const bvec3 negative = lessThan(floatBitsToInt(p), ivec3(0));
  outside = mix(intBitsToFloat(floatBitsToInt(p) + mix(steps, -steps, negative)), fma(n, vec3(eps), p), small);
  inside = mix(intBitsToFloat(floatBitsToInt(p) + mix(-steps, steps, negative)), fma(-n, vec3(eps), p), small);
}

// Where a ray from a surface point toward a light `distance` away ends: short of it by
// the scene's ray_epsilon or by RPU_RAY_OFFSET_ULPS of the format's relative precision
// 2^-M, whichever is more (docs/shading.md "Leaving a surface"), so that the surface the
// light lies on does not shadow it.
float rpu_ray_end(float distance) {
  const float relative = uintBitsToFloat((104u + scene_record.ray_offset_shift) << 23);  // 2^-M
  return min(distance - scene_record.ray_epsilon, distance * fma(relative, -float(RPU_RAY_OFFSET_ULPS), 1.0));
}

// The origin of a ray that leaves p on n's side (rpu_offset_rays).
vec3 rpu_offset_ray(vec3 p, vec3 n) {
  vec3 outside, inside;
  rpu_offset_rays(p, n, outside, inside);
  return outside;
}

#endif
