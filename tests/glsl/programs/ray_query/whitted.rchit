#version 460
#extension GL_EXT_ray_tracing : require
layout(location = 0) rayPayloadInEXT vec3 answer;
hitAttributeEXT vec2 uv;
void main() { answer = vec3(gl_HitTEXT, uv); }
