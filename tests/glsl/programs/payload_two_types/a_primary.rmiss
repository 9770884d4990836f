#version 460
#extension GL_EXT_ray_tracing : require
struct Probe {
  vec3 color;
  uint hits;
};
layout(location = 0) rayPayloadInEXT Probe probe;
void main() {
  probe.color = vec3(0.25, 0.0, 0.0);
  probe.hits = 7u;
}
