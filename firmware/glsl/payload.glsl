// The payload of the library's shaders: a ray's colour, its bounce depth (the primary
// ray is 0) and the sample's random stream, which every shader that draws passes on.
struct RpuRay {
  vec3 color;
  uint depth;
  uint stream;
};
