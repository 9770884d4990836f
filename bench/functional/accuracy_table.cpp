// The accuracy column of the speed/accuracy table: each scene rendered by the
// reference renderer and by the Whitted firmware on the functional device in every
// number format, PSNR (sRGB, dB) against the reference and the functional host time.
// Prints a Markdown table; --json FILE also writes one record per cell in the form of
// bench/results/accuracy.json, from which scripts/doc-tables makes docs/accuracy.md.
//
//   build/release/bench/functional/accuracy_table [--size 128] [--spp 4] [--json FILE]
//       [--commit HASH] [scenes...]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

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
  std::string json_path, commit = "unknown";
  std::vector<std::string> scenes;
  std::string command = "build/release/bench/functional/accuracy_table";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--json" || a == "--commit") && i + 1 < argc) {
      ++i;  // neither changes what is measured
    } else {
      command += " " + a;
    }
  }
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc) {
      size = std::stoi(argv[++i]);
    } else if (a == "--spp" && i + 1 < argc) {
      spp = std::stoi(argv[++i]);
    } else if (a == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else if (a == "--commit" && i + 1 < argc) {
      commit = argv[++i];
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
  nlohmann::json records = nlohmann::json::array();
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
        const double psnr = psnr_srgb(reference, image);
        row += fmt::format("| {:.1f} dB, {:.2f} s ", psnr, seconds);
        records.push_back({{"commit", commit},
                           {"command", command},
                           {"config",
                            {{"hardware", "default"}, {"width", size}, {"height", size}, {"spp", spp},
                             {"max_depth", settings.max_depth}, {"isect", "woop"}}},
                           {"scene", name},
                           {"format", f},
                           {"psnr_db", std::round(psnr * 10) / 10},
                           {"wall_s", std::round(seconds * 100) / 100}});
      }
      fmt::print("{}|\n", row);
      std::fflush(stdout);
    }
  } catch (const Error& e) {
    fmt::print(stderr, "accuracy_table: {}\n", e.what());
    return 1;
  }
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    for (const auto& r : records) out << r.dump() << ",\n";
    if (!out) {
      fmt::print(stderr, "accuracy_table: cannot write {}; check the directory exists and is writable\n", json_path);
      return 1;
    }
    fmt::print(stderr, "accuracy_table: {} records in {} (append them to bench/results/accuracy.json)\n",
               records.size(), json_path);
  }
  return 0;
}
