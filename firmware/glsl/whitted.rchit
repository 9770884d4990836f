// Whitted's recursive ray tracing with Phong's specular term: docs/shading.md sections 3
// and 4, computed as firmware/whitted.s computes it (the same operations in the same
// order, so that both give the same image).
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  vec3 color = direct_light(h, m.ambient.xyz, m.diffuse.xyz, m.specular.xyz, m.shininess);
  if (ray.depth < launch_record.max_depth) {
    const float kr = m.reflectance, kt = m.transmittance;
    if (0.0 < kr) color = fma(trace_secondary(h.outside, mirror_direction(h)), vec3(kr), color);
    if (0.0 < kt) {
      const float eta = h.entering ? 1.0 / m.ior : m.ior;
      const float cos_i = dot(h.d, -h.n);
      // precise: SPIRV-Tools would fuse these into fma, which whitted.s does not
      precise float k = fma(-cos_i, cos_i, 1.0);
      k = 1.0 - eta * eta * k;
      vec3 origin, direction;
      if (k < 0.0) {  // total internal reflection: kt goes to the mirror ray
        direction = mirror_direction(h);
        origin = h.outside;
      } else {
        precise const float a = eta * cos_i - sqrt(k);
        const vec3 t = fma(h.d, vec3(eta), h.n * a);
        direction = t * inversesqrt(dot(t, t));
        origin = h.inside;
      }
      color = fma(trace_secondary(origin, direction), vec3(kt), color);
    }
  }
  ray.color = color;
}
