#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "payload.glsl"
layout(location = 0) rayPayloadInEXT Probe probe;
void main() {
  probe.count -= 1u;
  probe.color = vec3(-1.0, -2.0, -3.0);
}
