// A ray that hits nothing: the scene's background (docs/shading.md section 4).
#version 460
#extension GL_EXT_ray_tracing : require
#include "rpu.glsl"
#include "whitted_payload.glsl"

layout(location = 0) rayPayloadInEXT WhittedRay ray;

void main() { ray.color = scene_record.background.xyz; }
