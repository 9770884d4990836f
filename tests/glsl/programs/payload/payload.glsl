struct Probe {
  vec3 color;
  uint count;
  float t;
  bool hit;
};
