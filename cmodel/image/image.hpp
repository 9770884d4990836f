#pragma once

#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

namespace rpu {

// A linear-light RGB image, row 0 at the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;  // width * height, row-major

  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, glm::vec3(0.0f)) {}
  glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec3& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

// IEC 61966-2-1 sRGB transfer function on a linear value in [0, 1].
double srgb_encode(double linear);
// Linear value -> 8-bit sRGB code, clamping to [0, 1] first.
unsigned char srgb_encode_8bit(double linear);

// A perceptually ordered ramp for heatmaps, dark blue -> cyan -> green -> yellow -> red
// over x in [0, 1] (clamped), in linear RGB.
glm::vec3 false_colour(double x);

// Throws rpu::Error naming the file unless its extension is one write_image knows;
// lets a caller reject a bad output name before hours of rendering.
void check_image_extension(const std::filesystem::path& file);

// Writes by extension: .png as 8-bit sRGB, .exr as linear 32-bit float (OpenImageIO),
// through an OutputFile: the image must read back at its size before it replaces the
// file. Throws rpu::Error naming the file on an unknown extension or a write failure,
// which leaves the old file as it was.
void write_image(const Image& image, const std::filesystem::path& file);

// Peak signal-to-noise ratio in dB of `test` against `reference` (same size), over
// the sRGB-encoded values clamped to [0, 1] (what a PNG shows), peak 1, all three
// channels; OpenImageIO's ImageBufAlgo::compare computes it. Identical images give
// +infinity.
double psnr_srgb(const Image& reference, const Image& test);

// Dark dots of `test` against `reference` (same size): pixels whose luminance is under
// kDarkDotRatio of the reference's while fewer than half of their neighbours (of the
// eight, those inside the image) are that dark. They are what a secondary ray that hits
// the surface it leaves draws (docs/accuracy.md "Dark dots"): isolated, where a shadow
// the reference has too, or any other difference of a region, is not.
inline constexpr double kDarkDotRatio = 0.6;
std::size_t dark_dots(const Image& reference, const Image& test);

// Reads any format OpenImageIO knows; PNG/JPEG come back as stored code values / 255
// (no sRGB decoding), EXR as stored linear values.
Image read_image(const std::filesystem::path& file);

}  // namespace rpu
