#include "render/sampling.hpp"

#include <cmath>
#include <numbers>

namespace rpu {

namespace {
constexpr std::uint32_t kLcgMultiplier = 747796405u;
constexpr std::uint32_t kLcgIncrement = 2891336453u;

// PCG's RXS-M-XS output permutation of a 32-bit state (O'Neill 2014, section 6.3.4).
std::uint32_t permute(std::uint32_t x) {
  const std::uint32_t word = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  return (word >> 22u) ^ word;
}

// One LCG step then the permutation: the "PCG hash" of Jarzynski and Olano (JCGT 2020),
// which decorrelates neighbouring pixel and sample numbers.
std::uint32_t hash(std::uint32_t x) { return permute(x * kLcgMultiplier + kLcgIncrement); }
}  // namespace

SampleStream::SampleStream(std::uint32_t seed, std::uint32_t pixel, std::uint32_t sample)
    : state_(hash(seed ^ hash(pixel ^ hash(sample)))) {}

std::uint32_t SampleStream::next_u32() {
  const std::uint32_t old = state_;
  state_ = old * kLcgMultiplier + kLcgIncrement;
  return permute(old);
}

// The top 23 bits as the fraction of a float in [1, 2), minus 1: what the firmware
// computes with integer and float instructions, exactly, in fp32.
double SampleStream::next_double() { return (next_u32() >> 9) * 0x1.0p-23; }

glm::dvec2 pixel_sample_offset(int sample, int spp, SampleStream& stream) {
  if (spp <= 1) return {0.5, 0.5};
  const glm::dvec2 jitter{stream.next_double(), stream.next_double()};
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(spp))));
  if (n * n != spp) return jitter;
  return {(sample % n + jitter.x) / n, (sample / n + jitter.y) / n};
}

CameraModel::CameraModel(const Camera& camera, int width, int height)
    : origin_(camera.position),
      forward_(glm::normalize(camera.look_at - camera.position)),
      width_(width),
      height_(height),
      aperture_radius_(camera.aperture_radius) {
  right_ = glm::normalize(glm::cross(forward_, camera.up));
  up_ = glm::cross(right_, forward_);
  half_height_ = std::tan(camera.vfov_degrees * std::numbers::pi / 360.0);
  half_width_ = half_height_ * width / height;
  focus_distance_ = camera.focus_distance > 0.0 ? camera.focus_distance
                                                : glm::length(camera.look_at - camera.position);
}

PrimaryRay CameraModel::ray(double px, double py, glm::dvec2 lens) const {
  const double sx = (2.0 * px / width_ - 1.0) * half_width_;
  const double sy = (1.0 - 2.0 * py / height_) * half_height_;
  const glm::dvec3 d = forward_ + sx * right_ + sy * up_;
  if (aperture_radius_ <= 0.0) return {origin_, glm::normalize(d)};
  // Thin lens: every ray through the lens disk meets the pinhole ray on the focal plane.
  const glm::dvec3 focus = origin_ + d * focus_distance_;
  const double r = aperture_radius_ * std::sqrt(lens.x);
  const double phi = 2.0 * std::numbers::pi * lens.y;
  const glm::dvec3 o = origin_ + r * (std::cos(phi) * right_ + std::sin(phi) * up_);
  return {o, glm::normalize(focus - o)};
}

}  // namespace rpu
