// The Whitted firmware on the functional device against the double-precision
// reference renderer (docs/shading.md is the one description both implement), and
// the functional model's promise that the image depends on nothing but the inputs.
#include <gtest/gtest.h>

#include <cstring>

#include <fmt/format.h>

#include "common/hardware_config.hpp"
#include "device/builtin_firmware.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

RenderSettings small_settings() {
  RenderSettings s;
  s.width = 80;
  s.height = 80;
  s.spp = 4;
  s.max_depth = 5;
  s.seed = 7;
  return s;
}

Image render_functional(const Scene& scene, const RenderSettings& settings, std::string_view config_name,
                        fp::Format format, int host_threads) {
  const spec::HardwareConfig& config = hardware_config(config_name);
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  build.format = format;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  device::FunctionalOptions options;
  options.host_threads = host_threads;
  const auto dev = device::make_functional_device(config, format, options);
  return device::render_frame(*dev, scene, si.image, device::builtin_firmware("whitted.s"), settings);
}

class WhittedScene : public testing::TestWithParam<std::string> {};

// Issue 4: functional fp32 images of the Cornell box, SPD balls and the bunny within
// 40 dB PSNR of the reference. Measured values are in docs/accuracy.md.
TEST_P(WhittedScene, Fp32MatchesTheReferenceWithin40dB) {
  const Scene scene = resolve_scene(GetParam());
  const RenderSettings settings = small_settings();
  const Image reference = ReferenceRenderer(scene).render(settings);
  const Image functional = render_functional(scene, settings, "default", fp::kFp32, 2);
  const double psnr = psnr_srgb(reference, functional);
  RecordProperty("psnr_db", fmt::format("{:.1f}", psnr));
  EXPECT_GE(psnr, 40.0) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Scenes, WhittedScene, testing::Values("cornell", "balls:2", "scenes/bunny.json"),
                         [](const testing::TestParamInfo<std::string>& i) {
                           return i.param == "scenes/bunny.json" ? std::string("bunny")
                                                                 : i.param.substr(0, i.param.find(':'));
                         });

bool same_pixels(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// The image is a function of scene, settings, format and firmware only: not of the
// chunk size (tiny: 2, default: 4), the number of cores and threads, or host threads.
TEST(Whitted, ImageDoesNotDependOnChunkSizeThreadsOrHostThreads) {
  const Scene scene = resolve_scene("cornell");
  RenderSettings settings = small_settings();
  settings.width = 40;
  settings.height = 30;
  const Image a = render_functional(scene, settings, "default", fp::kFp32, 1);
  const Image b = render_functional(scene, settings, "default", fp::kFp32, 2);
  const Image c = render_functional(scene, settings, "tiny", fp::kFp32, 2);
  EXPECT_TRUE(same_pixels(a, b)) << "host threads changed the image";
  EXPECT_TRUE(same_pixels(a, c)) << "the configuration (chunk size, thread count) changed the image";
}

// Narrower formats render through the same firmware; the reference-relative PSNR of
// each is the accuracy column of docs/accuracy.md. Formats with fp32's exponent range
// stay close; the floor here only catches a broken soft path.
TEST(Whitted, NarrowFormatsRender) {
  const Scene scene = resolve_scene("cornell");
  const RenderSettings settings = small_settings();
  const Image reference = ReferenceRenderer(scene).render(settings);
  for (const std::string_view name : {"e8m15", "rpu24"}) {
    const double psnr = psnr_srgb(reference, render_functional(scene, settings, "default", fp::format_by_name(name), 2));
    RecordProperty(fmt::format("psnr_db_{}", name), fmt::format("{:.1f}", psnr));
    EXPECT_GE(psnr, 35.0) << name;
  }
}

}  // namespace
}  // namespace rpu
