#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "payload.glsl"
layout(location = 0) rayPayloadInEXT Probe probe;
hitAttributeEXT vec2 uv;
void main() {
  probe.count += 1u;
  probe.t = gl_HitTEXT;
  probe.hit = true;
  const bool inside = uv.x >= 0.0 && uv.y >= 0.0 && uv.x + uv.y <= 1.0;
  const bool same = gl_RayTmaxEXT == gl_HitTEXT && gl_RayTminEXT == 0.0 &&
                    gl_WorldRayDirectionEXT == launch_record.forward.xyz &&
                    gl_WorldRayOriginEXT == launch_record.origin.xyz &&
                    uint(gl_InstanceCustomIndexEXT) == triangles[gl_PrimitiveID].material;
  probe.color = vec3(float(gl_PrimitiveID), inside && same ? 1.0 : 0.0, 0.0);
}
