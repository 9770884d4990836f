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

#endif
