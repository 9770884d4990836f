// The payload of the Whitted shaders: a ray's colour, its bounce depth (the primary ray
// is 0) and the sample's random stream, which every shader that draws passes on.
struct WhittedRay {
  vec3 color;
  uint depth;
  uint stream;
};
