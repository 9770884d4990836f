#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
layout(location = 0) rayPayloadInEXT uint depth;
layout(location = 1) rayPayloadEXT uint deeper;
void main() {
  // one level past what --max-depth 2 allows
  if (depth < 4u) {
    deeper = depth + 1u;
    traceRayEXT(scene_bvh, gl_RayFlagsOpaqueEXT, 0xff, 0, 0, 0, gl_WorldRayOriginEXT, 0.0, gl_WorldRayDirectionEXT,
                RPU_INFINITY, 1);
    depth = deeper;
  }
}
