// Phong: the material's ambient, diffuse and specular terms under the scene's lights,
// with shadows; no secondary rays.
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  ray.color = direct_light(h, m.ambient.xyz, m.diffuse.xyz, m.specular.xyz, m.shininess);
}
