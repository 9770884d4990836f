#version 460
#extension GL_EXT_ray_tracing : require
struct Probe {
  vec3 color;
  uint hits;
};
layout(location = 0) rayPayloadInEXT Probe probe;
void main() { probe.hits = 100u; }
