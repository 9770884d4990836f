// A mirror: the material's Phong terms plus the mirror ray, tinted by the specular colour.
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  vec3 color = direct_light(h, m.ambient.xyz, m.diffuse.xyz, m.specular.xyz, m.shininess);
  if (ray.depth < launch_record.max_depth) color += m.specular.xyz * trace_secondary(h.outside, mirror_direction(h));
  ray.color = color;
}
