// What the library's closest-hit shaders share (docs/shading.md sections 3 and 4), in
// the operations and order of firmware/whitted.s, so that whitted.rchit renders its image.
// Include after rpu.glsl in a closest-hit shader.
#ifndef RPU_SHADING_GLSL
#define RPU_SHADING_GLSL
#extension GL_EXT_ray_query : require
#include "payload.glsl"

layout(location = 0) rayPayloadInEXT RpuRay ray;
layout(location = 1) rayPayloadEXT RpuRay secondary;
hitAttributeEXT vec2 barycentrics;

// v / |v| and |v|, the vector first scaled by the power of two that brings its largest
// component into [1, 2) (rpu_binade_down), so that its squared length neither overflows
// nor flushes in a narrow format; one inversesqrt gives both.
vec3 unit(vec3 v, out float len) {
  const float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
  v = v * rpu_binade_down(m);
  const float len2 = dot(v, v);
  const float r = inversesqrt(len2);
  len = (len2 * r) * rpu_binade(m);
  return v * r;
}

// The colour a ray from `origin` along `direction` brings back: one bounce deeper, on the
// sample's stream.
vec3 trace_secondary(vec3 origin, vec3 direction) {
  secondary.depth = ray.depth + 1u;
  secondary.stream = ray.stream;
  traceRayEXT(scene_bvh, gl_RayFlagsOpaqueEXT, 0xff, 0, 0, 0, origin, 0.0, direction, RPU_INFINITY, 1);
  ray.stream = secondary.stream;
  return secondary.color;
}

// The hit point: P, the geometric normal Ng and the shading normal N (both turned to
// face the viewer), whether the ray enters the object, the points off the surface on
// either side (rpu_offset_rays) and the scene's ray epsilon.
struct Hit {
  vec3 d;
  vec3 p;
  vec3 ng;
  vec3 n;
  bool entering;
  vec3 outside;
  vec3 inside;
  float eps;
};

Hit hit_point() {
  Hit h;
  h.d = gl_WorldRayDirectionEXT;
  h.eps = scene_record.ray_epsilon;
  const Triangle tri = triangles[gl_PrimitiveID];
  const vec3 p0 = positions[tri.a].xyz;
  vec3 e1 = positions[tri.b].xyz - p0;
  vec3 e2 = positions[tri.c].xyz - p0;
  // P = p0 + u (p1 - p0) + v (p2 - p0): on the triangle's plane to rounding, however far
  // the ray came.
  h.p = fma(e2, vec3(barycentrics.y), fma(e1, vec3(barycentrics.x), p0));
  e1 = e1 * rpu_binade_down(max(max(abs(e1.x), abs(e1.y)), abs(e1.z)));
  e2 = e2 * rpu_binade_down(max(max(abs(e2.x), abs(e2.y)), abs(e2.z)));
  float len;
  h.ng = unit(fma(e1.yzx, e2.zxy, -(e1.zxy * e2.yzx)), len);
  h.n = h.ng;
  if (launch_record.normals != 0u) {
    const float u = barycentrics.x, v = barycentrics.y;
    const float w = 1.0 - u - v;
    vec3 blend = normals[tri.a].xyz * w;
    blend = fma(normals[tri.b].xyz, vec3(u), blend);
    blend = fma(normals[tri.c].xyz, vec3(v), blend);
    const float len2 = dot(blend, blend);
    if (0.0 < len2) {
      h.n = blend * inversesqrt(len2);
      if (dot(h.n, h.ng) < 0.0) h.n = -h.n;  // turned to Ng's side
    }
  }
  h.entering = dot(h.d, h.ng) < 0.0;
  if (!h.entering) {  // leaving: both normals face the viewer
    h.ng = -h.ng;
    h.n = -h.n;
  }
  rpu_offset_rays(h.p, h.ng, h.outside, h.inside);
  return h;
}

// ka + the lights visible from the hit, each kd (N.L) + ks max(0, R.V)^n; an area light
// is sampled at one point per shading point (soft shadows over the pixel's samples).
vec3 direct_light(Hit h, vec3 ka, vec3 kd, vec3 ks, float shininess) {
  vec3 color = ka;
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
      l = unit(at - h.p, distance);
    }
    const float n_dot_l = dot(h.n, l);
    if (n_dot_l <= 0.0) continue;
    if (dot(h.ng, l) <= 0.0) continue;
    // the shadow ray: any hit over (0, rpu_ray_end(distance))
    rayQueryEXT shadow;
    rayQueryInitializeEXT(shadow, scene_bvh, gl_RayFlagsTerminateOnFirstHitEXT, 0xff, h.outside, 0.0, l,
                          rpu_ray_end(distance));
    rayQueryProceedEXT(shadow);
    if (rayQueryGetIntersectionTypeEXT(shadow, true) != gl_RayQueryCommittedIntersectionNoneEXT) continue;
    const vec3 r = h.n * (n_dot_l + n_dot_l) - l;  // the mirror of L about N
    const float r_dot_v = dot(r, -h.d);
    float specular = 0.0;
    if (0.0 < r_dot_v) specular = pow(r_dot_v, shininess);
    const vec3 local = fma(ks, vec3(specular), kd * n_dot_l);
    color = fma(light.color.xyz, local, color);
  }
  return color;
}

// d - 2 (d . N) N
vec3 mirror_direction(Hit h) {
  const float d_dot_n = dot(h.d, h.n);
  return h.d - h.n * (d_dot_n + d_dot_n);
}

#endif
