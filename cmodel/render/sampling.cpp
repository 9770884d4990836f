#include "render/sampling.hpp"

#include <cmath>
#include <numbers>

namespace rpu {

namespace {
constexpr std::uint64_t kLcgMultiplier = 6364136223846793005ull;
constexpr std::uint64_t kLcgIncrement = 1442695040888963407ull;

// SplitMix64 finaliser: decorrelates neighbouring pixel and sample numbers.
std::uint64_t mix64(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
}  // namespace

SampleStream::SampleStream(std::uint64_t seed, std::uint64_t pixel, std::uint32_t sample)
    : state_(mix64(seed ^ mix64(pixel ^ mix64(sample)))) {}

std::uint32_t SampleStream::next_u32() {
  const std::uint64_t old = state_;
  state_ = old * kLcgMultiplier + kLcgIncrement;
  const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
  const auto rot = static_cast<std::uint32_t>(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

double SampleStream::next_double() { return next_u32() * 0x1.0p-32; }

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
