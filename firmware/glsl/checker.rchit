// A procedural checker texture: the diffuse colour in squares of a tenth of the scene's
// size (1000 ray epsilons: docs/shading.md), alternating with a fifth of it, lit as Phong.
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  const vec3 cell = floor(h.p * (1.0 / (1000.0 * h.eps)) + 0.5 * h.ng);
  const int parity = (int(cell.x) + int(cell.y) + int(cell.z)) & 1;
  const vec3 kd = parity == 0 ? m.diffuse.xyz : 0.2 * m.diffuse.xyz;
  ray.color = direct_light(h, m.ambient.xyz, kd, m.specular.xyz, m.shininess);
}
