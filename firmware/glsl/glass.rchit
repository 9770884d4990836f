// Glass with Fresnel: the reflected and refracted rays weighted by Schlick's
// approximation R = R0 + (1 - R0)(1 - cos)^5, R0 = ((ior - 1) / (ior + 1))^2, with cos
// the angle on the outside; total internal reflection sends everything to the mirror.
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "shading.glsl"

void main() {
  const Hit h = hit_point();
  const Material m = materials[gl_InstanceCustomIndexEXT];
  vec3 color = direct_light(h, m.ambient.xyz, vec3(0.0), m.specular.xyz, m.shininess);
  if (ray.depth < launch_record.max_depth) {
    const float eta = h.entering ? 1.0 / m.ior : m.ior;
    const float cos_i = dot(h.d, -h.n);
    const float k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    float reflect_weight = 1.0;
    vec3 refracted = vec3(0.0);
    if (k >= 0.0) {
      const float cos_t = sqrt(k);
      const float r0 = (m.ior - 1.0) / (m.ior + 1.0);
      const float c = 1.0 - (h.entering ? cos_i : cos_t);
      const float c2 = c * c;
      reflect_weight = fma(1.0 - r0 * r0, c2 * c2 * c, r0 * r0);
      const vec3 t = normalize(fma(h.d, vec3(eta), h.n * (eta * cos_i - cos_t)));
      refracted = trace_secondary(h.inside, t);
    }
    const vec3 reflected = trace_secondary(h.outside, mirror_direction(h));
    color += m.diffuse.xyz * (reflect_weight * reflected + (1.0 - reflect_weight) * refracted);
  }
  ray.color = color;
}
