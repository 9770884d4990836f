// Whitted's recursive ray tracing with Phong's specular term: docs/shading.md sections 3
// and 4, computed as firmware/whitted.s computes it (the same operations in the same
// order, so that both give the same image).
#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_EXT_ray_query : require
#include "rpu.glsl"
#include "whitted_payload.glsl"

layout(location = 0) rayPayloadInEXT WhittedRay ray;
layout(location = 1) rayPayloadEXT WhittedRay secondary;
hitAttributeEXT vec2 barycentrics;

// v / |v| and |v|, the vector first divided by its largest component, so that its
// squared length neither overflows nor flushes in a narrow format.
vec3 unit(vec3 v, out float len) {
  const float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
  v = v * (1.0 / m);
  const float len2 = dot(v, v);
  len = sqrt(len2) * m;
  return v * inversesqrt(len2);
}

vec3 trace_secondary(vec3 origin, vec3 direction) {
  secondary.depth = ray.depth + 1u;
  secondary.stream = ray.stream;
  traceRayEXT(scene_bvh, gl_RayFlagsOpaqueEXT, 0xff, 0, 0, 0, origin, 0.0, direction, RPU_INFINITY, 1);
  ray.stream = secondary.stream;
  return secondary.color;
}

void main() {
  const vec3 d = gl_WorldRayDirectionEXT;
  const float eps = scene_record.ray_epsilon;
  const vec3 p = fma(d, vec3(gl_HitTEXT), gl_WorldRayOriginEXT);
  const Triangle tri = triangles[gl_PrimitiveID];
  const Material m = materials[gl_InstanceCustomIndexEXT];
  const vec3 p0 = positions[tri.a].xyz;
  vec3 e1 = positions[tri.b].xyz - p0;
  vec3 e2 = positions[tri.c].xyz - p0;
  e1 = e1 * (1.0 / max(max(abs(e1.x), abs(e1.y)), abs(e1.z)));
  e2 = e2 * (1.0 / max(max(abs(e2.x), abs(e2.y)), abs(e2.z)));
  float len;
  vec3 ng = unit(fma(e1.yzx, e2.zxy, -(e1.zxy * e2.yzx)), len);
  vec3 nrm = ng;
  if (launch_record.normals != 0u) {
    const float u = barycentrics.x, v = barycentrics.y;
    const float w = 1.0 - u - v;
    vec3 blend = normals[tri.a].xyz * w;
    blend = fma(normals[tri.b].xyz, vec3(u), blend);
    blend = fma(normals[tri.c].xyz, vec3(v), blend);
    const float len2 = dot(blend, blend);
    if (0.0 < len2) {
      nrm = blend * inversesqrt(len2);
      if (dot(nrm, ng) < 0.0) nrm = -nrm;  // turned to Ng's side
    }
  }
  const bool entering = dot(d, ng) < 0.0;
  if (!entering) {  // leaving: both normals face the viewer
    ng = -ng;
    nrm = -nrm;
  }
  const vec3 outside = fma(ng, vec3(eps), p);
  vec3 color = m.ambient.xyz;

  for (uint k = 0u; k < scene_record.light_count; ++k) {
    const Light light = lights[k];
    vec3 l;
    float distance;
    if (light.kind == LIGHT_KIND_DIRECTIONAL) {
      l = -light.direction.xyz;
      distance = RPU_INFINITY;
    } else {
      vec3 at = light.position.xyz;
      if (light.kind == LIGHT_KIND_AREA) {  // a point of the rectangle
        at = fma(light.edge_u.xyz, vec3(rpu_random(ray.stream)), at);
        at = fma(light.edge_v.xyz, vec3(rpu_random(ray.stream)), at);
      }
      l = unit(at - p, distance);
    }
    const float n_dot_l = dot(nrm, l);
    if (n_dot_l <= 0.0) continue;
    if (dot(ng, l) <= 0.0) continue;
    // the shadow ray: any hit over (0, distance - eps)
    rayQueryEXT shadow;
    rayQueryInitializeEXT(shadow, scene_bvh, gl_RayFlagsTerminateOnFirstHitEXT, 0xff, outside, 0.0, l,
                          distance - eps);
    rayQueryProceedEXT(shadow);
    if (rayQueryGetIntersectionTypeEXT(shadow, true) != gl_RayQueryCommittedIntersectionNoneEXT) continue;
    const vec3 r = nrm * (n_dot_l + n_dot_l) - l;  // the mirror of L about N
    const float r_dot_v = dot(r, -d);
    float specular = 0.0;
    if (0.0 < r_dot_v) specular = pow(r_dot_v, m.shininess);
    const vec3 local = fma(m.specular.xyz, vec3(specular), m.diffuse.xyz * n_dot_l);
    color = fma(light.color.xyz, local, color);
  }

  if (ray.depth < launch_record.max_depth) {
    const float kr = m.reflectance, kt = m.transmittance;
    if (0.0 < kr) {
      const float d_dot_n = dot(d, nrm);
      const vec3 reflected = d - nrm * (d_dot_n + d_dot_n);
      color = fma(trace_secondary(outside, reflected), vec3(kr), color);
    }
    if (0.0 < kt) {
      const float eta = entering ? 1.0 / m.ior : m.ior;
      const float cos_i = dot(d, -nrm);
      // precise: SPIRV-Tools would fuse these into fma, which whitted.s does not
      precise float k = fma(-cos_i, cos_i, 1.0);
      k = 1.0 - eta * eta * k;
      vec3 origin, direction;
      if (k < 0.0) {  // total internal reflection: kt goes to the mirror ray
        const float d_dot_n = dot(d, nrm);
        direction = d - nrm * (d_dot_n + d_dot_n);
        origin = outside;
      } else {
        precise const float a = eta * cos_i - sqrt(k);
        const vec3 t = fma(d, vec3(eta), nrm * a);
        direction = t * inversesqrt(dot(t, t));
        origin = fma(ng, vec3(-eps), p);
      }
      color = fma(trace_secondary(origin, direction), vec3(kt), color);
    }
  }
  ray.color = color;
}
