#include "image/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/output_file.hpp"

namespace rpu {

double srgb_encode(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

unsigned char srgb_encode_8bit(double linear) {
  return static_cast<unsigned char>(std::lround(srgb_encode(linear) * 255.0));
}

glm::vec3 false_colour(double x) {
  static const glm::vec3 stops[] = {{0.0f, 0.0f, 0.15f}, {0.0f, 0.45f, 0.9f}, {0.1f, 0.8f, 0.2f},
                                    {0.95f, 0.85f, 0.0f}, {0.9f, 0.05f, 0.0f}};
  const double s = std::clamp(x, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(s));
  const float f = static_cast<float>(s - i);
  return stops[i] * (1.0f - f) + stops[i + 1] * f;
}

void check_image_extension(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext != ".png" && ext != ".exr") {
    throw Error(fmt::format("{}: unknown image type '{}': use .png (8-bit sRGB) or .exr (linear float)",
                            file.string(), ext));
  }
}

namespace {

// OpenImageIO's errors may span lines (one per library layer): one line for rpu::Error.
std::string one_line(std::string text) {
  while (!text.empty() && text.back() == '\n') text.pop_back();
  for (std::size_t at; (at = text.find('\n')) != std::string::npos;) text.replace(at, 1, "; ");
  return text;
}

}  // namespace

void write_image(const Image& image, const std::filesystem::path& file) {
  check_image_extension(file);
  const bool png = file.extension() == ".png";
  OutputFile output(file);
  const std::string temp = output.temp_path().string();
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(temp);
  if (!out) output.fail(fmt::format("cannot create an image writer: {}", one_line(OIIO::geterror())));
  OIIO::ImageSpec spec(image.width, image.height, 3, png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
  bool ok = out->open(temp, spec);
  if (ok && png) {
    std::vector<unsigned char> bytes(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      for (int c = 0; c < 3; ++c) bytes[3 * i + c] = srgb_encode_8bit(image.pixels[i][c]);
    }
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  } else if (ok) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
  }
  if (ok) ok = out->close();
  if (!ok) output.fail(one_line(out->geterror()));
  // OpenImageIO's PNG writer reports success when the disk filled up under it: only a
  // file that reads back whole, at its size, replaces the target.
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(temp);
  if (!in) output.fail(fmt::format("it does not read back: {}", one_line(OIIO::geterror())));
  const OIIO::ImageSpec& back = in->spec();
  if (back.width != image.width || back.height != image.height || back.nchannels != 3) {
    output.fail(fmt::format("it reads back as {}x{} pixels of {} channels, expected {}x{} of 3", back.width,
                            back.height, back.nchannels, image.width, image.height));
  }
  std::vector<float> pixels(image.pixels.size() * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data())) {
    output.fail(fmt::format("it does not read back: {}", one_line(in->geterror())));
  }
  in->close();
  output.commit();
}

Image read_image(const std::filesystem::path& file) {
  check_input_file(file, "the image");
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  if (!in) throw Error(fmt::format("{}: cannot read image: {}", file.string(), OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> data(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data())) {
    throw Error(fmt::format("{}: cannot read image: {}", file.string(), in->geterror()));
  }
  Image image(spec.width, spec.height);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      image.pixels[i][c] = data[i * spec.nchannels + static_cast<std::size_t>(std::min(c, spec.nchannels - 1))];
    }
  }
  return image;
}

double psnr_srgb(const Image& reference, const Image& test) {
  if (reference.width != test.width || reference.height != test.height) {
    throw Error(fmt::format("psnr: images of {}x{} and {}x{} pixels", reference.width, reference.height, test.width,
                            test.height));
  }
  const auto encoded = [](const Image& image) {
    OIIO::ImageBuf buf(OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT));
    std::vector<float> values;
    values.reserve(image.pixels.size() * 3);
    for (const glm::vec3& p : image.pixels) {
      for (int c = 0; c < 3; ++c) values.push_back(static_cast<float>(srgb_encode(std::clamp(double(p[c]), 0.0, 1.0))));
    }
    buf.set_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, values.data());
    return buf;
  };
  const OIIO::ImageBuf a = encoded(test), b = encoded(reference);
  // Thresholds above any difference of [0, 1] values: only the statistics are wanted
  // (OpenImageIO flags error when any value fails the threshold).
  const OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(a, b, 2.0f, 2.0f);
  if (r.error) throw Error(fmt::format("psnr: OpenImageIO could not compare the images: {}{}", a.geterror(), b.geterror()));
  return r.meanerror == 0.0 ? std::numeric_limits<double>::infinity() : r.PSNR;
}

std::size_t dark_dots(const Image& reference, const Image& test) {
  if (reference.width != test.width || reference.height != test.height) {
    throw Error(fmt::format("dark dots: images of {}x{} and {}x{} pixels", reference.width, reference.height,
                            test.width, test.height));
  }
  // Rec. 709 luminance of linear values; a NaN is not dark (the PSNR reports it).
  const auto luminance = [](const glm::vec3& p) { return 0.2126 * p.r + 0.7152 * p.g + 0.0722 * p.b; };
  std::vector<char> dark(test.pixels.size());
  for (std::size_t i = 0; i < dark.size(); ++i) {
    dark[i] = luminance(test.pixels[i]) < kDarkDotRatio * luminance(reference.pixels[i]);
  }
  std::size_t dots = 0;
  for (int y = 0; y < test.height; ++y) {
    for (int x = 0; x < test.width; ++x) {
      if (!dark[static_cast<std::size_t>(y) * test.width + x]) continue;
      int neighbours = 0, dark_neighbours = 0;
      for (int ny = std::max(0, y - 1); ny <= std::min(test.height - 1, y + 1); ++ny) {
        for (int nx = std::max(0, x - 1); nx <= std::min(test.width - 1, x + 1); ++nx) {
          if (nx == x && ny == y) continue;
          ++neighbours;
          dark_neighbours += dark[static_cast<std::size_t>(ny) * test.width + nx];
        }
      }
      if (2 * dark_neighbours < neighbours) ++dots;
    }
  }
  return dots;
}

}  // namespace rpu
