#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace rpu {

// A small random stream: PCG RXS-M-XS 32/32 (O'Neill 2014) seeded by (seed, pixel,
// sample) so every pixel's samples are independent of which thread renders it and of
// the order pixels are rendered in. 32-bit integer arithmetic only, so that the
// firmware computes the same numbers (docs/shading.md section 1).
class SampleStream {
 public:
  SampleStream(std::uint32_t seed, std::uint32_t pixel, std::uint32_t sample);
  std::uint32_t next_u32();
  double next_double();  // uniform in [0, 1), 23 random bits

 private:
  std::uint32_t state_;
};

// The position of sample `sample` of `spp` inside a pixel, in [0, 1)^2. One sample is
// the pixel centre; a square spp is a jittered n x n grid; otherwise uniform jitter.
glm::dvec2 pixel_sample_offset(int sample, int spp, SampleStream& stream);

struct PrimaryRay {
  glm::dvec3 origin;
  glm::dvec3 direction;  // unit length
};

// Camera rays for an image of width x height pixels, row 0 at the top.
class CameraModel {
 public:
  CameraModel(const Camera& camera, int width, int height);
  // (px, py): image-plane position in pixels, e.g. x + 0.5 for a pixel centre.
  // lens: a sample in [0, 1)^2, used only by a thin-lens camera.
  PrimaryRay ray(double px, double py, glm::dvec2 lens) const;

  // The frame of docs/shading.md §2: unit forward, right and up, and the image plane's
  // half extent at distance 1 along forward.
  const glm::dvec3& origin() const { return origin_; }
  const glm::dvec3& forward() const { return forward_; }
  const glm::dvec3& right() const { return right_; }
  const glm::dvec3& up() const { return up_; }
  double half_width() const { return half_width_; }
  double half_height() const { return half_height_; }

 private:
  glm::dvec3 origin_, forward_, right_, up_;
  double half_width_, half_height_;
  int width_, height_;
  double aperture_radius_, focus_distance_;
};

}  // namespace rpu
