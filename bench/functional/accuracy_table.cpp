// The accuracy column of the speed/accuracy table: each scene rendered by the
// reference renderer and by the Whitted firmware on the functional device in every
// number format, PSNR (sRGB, dB) against the reference and the functional host time.
// Prints a Markdown table (docs/accuracy.md).
//
//   build/release/bench/functional/accuracy_table [--size 128] [--spp 4] [scenes...]
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "scene/resolve.hpp"

int main(int argc, char** argv) {
  using namespace rpu;
  int size = 128, spp = 4;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc) {
      size = std::stoi(argv[++i]);
    } else if (a == "--spp" && i + 1 < argc) {
      spp = std::stoi(argv[++i]);
    } else {
      scenes.push_back(a);
    }
  }
  if (scenes.empty()) scenes = {"cornell", "balls:2", "scenes/bunny.json"};
  RenderSettings settings;
  settings.width = settings.height = size;
  settings.spp = spp;
  const char* formats[] = {"fp32", "e8m15", "rpu24", "bf16", "fp16"};
  std::string rule = "|---|";
  for (std::size_t i = 0; i < std::size(formats); ++i) rule += "--:|";
  fmt::print("| scene | {} |\n{}\n", fmt::join(formats, " | "), rule);
  try {
    const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
    for (const std::string& name : scenes) {
      const Scene scene = resolve_scene(name);
      const Image reference = ReferenceRenderer(scene).render(settings);
      std::string row = fmt::format("| {} ", name);
      for (const char* f : formats) {
        KdBuildConfig build = kd_build_config_for("default");
        build.format = fp::format_by_name(f);
        const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
        const auto dev = device::make_functional_device(hardware_config("default"), build.format);
        const auto start = std::chrono::steady_clock::now();
        const Image image = device::render_frame(*dev, scene, si.image, firmware, settings);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        row += fmt::format("| {:.1f} dB, {:.2f} s ", psnr_srgb(reference, image), seconds);
      }
      fmt::print("{}|\n", row);
      std::fflush(stdout);
    }
  } catch (const Error& e) {
    fmt::print(stderr, "accuracy_table: {}\n", e.what());
    return 1;
  }
  return 0;
}
