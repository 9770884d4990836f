// A glossy reflector: the material's Phong terms plus one reflected ray per shading point,
// drawn from a lobe about the mirror direction whose spread is the material's roughness
// (docs/shaders.md "The library"). Roughness 0 is the mirror of whitted.rchit.
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

// The mirror direction r moved by a uniform point of the disk of radius `roughness` at
// right angles to it (radius roughness sqrt(xi1), angle 2 pi xi2: two draws of the
// sample's stream), normalised; a direction that would leave below the surface is r.
vec3 glossy_direction(Hit h, vec3 r, float roughness) {
  const float xi1 = rpu_random(ray.stream);
  const float xi2 = rpu_random(ray.stream);
  // an orthonormal basis (r, u, v) without a division by a small number (Duff et al. 2017)
  const float s = r.z >= 0.0 ? 1.0 : -1.0;
  const float a = -1.0 / (s + r.z);
  const float b = r.x * r.y * a;
  const vec3 u = vec3(1.0 + s * r.x * r.x * a, s * b, -s * r.x);
  const vec3 v = vec3(b, s + r.y * r.y * a, -r.y);
  const float radius = roughness * sqrt(xi1);
  const float phi = 6.28318530718 * xi2;
  vec3 g = r + u * (radius * cos(phi)) + v * (radius * sin(phi));
  g = g * inversesqrt(dot(g, g));
  return dot(g, h.ng) > 0.0 ? g : r;
}

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  vec3 color = direct_light(h, m.ambient.xyz, m.diffuse.xyz, m.specular.xyz, m.shininess);
  if (ray.depth < launch_record.max_depth && m.reflectance > 0.0) {
    const vec3 r = glossy_direction(h, mirror_direction(h), m.roughness);
    color += m.reflectance * trace_secondary(h.outside, r);
  }
  ray.color = color;
}
