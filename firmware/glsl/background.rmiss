// A ray that hits nothing: the scene's background (docs/shading.md section 4).
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "payload.glsl"

layout(location = 0) rayPayloadInEXT RpuRay ray;

void main() { ray.color = scene_record.background.xyz; }
