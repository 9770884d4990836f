// The GLSL Whitted (firmware/glsl/whitted.*) against the hand-written assembly
// (firmware/whitted.s) on the functional device: the same image, bit for bit, in fp32 and
// in a narrow format, and the compiled code's instruction count against the assembly's.
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "cc/compiler.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

struct Frame {
  Image image;
  std::uint64_t instructions = 0;
  std::uint64_t rays = 0;
};

Frame render(const Scene& scene, const isa::Firmware& firmware, fp::Format format) {
  const spec::HardwareConfig& config = hardware_config("default");
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  build.format = format;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const auto dev = device::make_functional_device(config, format);
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.spp = 4;
  settings.max_depth = 5;
  settings.seed = 3;
  Frame r;
  r.image = device::render_frame(*dev, scene, si.image, firmware, settings);
  r.instructions = dev->stats().shader.instructions();
  r.rays = dev->stats().shader.closest_rays + dev->stats().shader.any_rays;
  return r;
}

// The library's ray generation, the hit shader `hit` and the miss shader, compiled once.
const cc::Compiled& library(const std::string& hit, int opt_level, int registers) {
  static std::map<std::tuple<std::string, int, int>, cc::Compiled> compiled;
  const auto key = std::make_tuple(hit, opt_level, registers);
  if (!compiled.count(key)) {
    const std::filesystem::path dir = RPU_GLSL_LIBRARY_DIR;
    cc::CompileOptions options;
    options.opt_level = opt_level;
    options.registers = registers;
    options.listing = true;  // its spills, counted
    compiled[key] = cc::compile_files({dir / "whitted.rgen", dir / (hit + ".rchit"), dir / "background.rmiss"}, options);
  }
  return compiled[key];
}

struct Case {
  std::string scene;
  std::string format;
  int opt_level = 2;
  int registers = 16;
  friend void PrintTo(const Case& c, std::ostream* os) {
    *os << c.scene << " " << c.format << " -O" << c.opt_level << " --registers " << c.registers;
  }
};

class GlslWhitted : public testing::TestWithParam<Case> {};

// Issue 18: the GLSL Whitted renders the test scenes as the assembly does (the goal:
// identical images), at -O2 with at most 1.3x its instructions (at -O0, or compiled
// for fewer registers than it needs so that values are spilled, the ratio is only
// recorded).
TEST_P(GlslWhitted, RendersTheAssemblysImageWithin1_3xItsInstructions) {
  const Scene scene = resolve_scene(GetParam().scene);
  const fp::Format format = fp::format_by_name(GetParam().format);
  const Frame assembly = render(scene, isa::builtin_firmware("whitted.s"), format);
  const cc::Compiled& whitted = library("whitted", GetParam().opt_level, GetParam().registers);
  if (GetParam().registers != 16) {
    EXPECT_NE(whitted.listing.find(": spill"), std::string::npos) << "nothing spilled: the case tests nothing";
  }
  const Frame compiled = render(scene, whitted.firmware, format);
  ASSERT_EQ(compiled.image.pixels.size(), assembly.image.pixels.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < compiled.image.pixels.size(); ++i) {
    differ += std::memcmp(&compiled.image.pixels[i], &assembly.image.pixels[i], sizeof(glm::vec3)) != 0;
  }
  EXPECT_EQ(differ, 0u) << "pixels that differ from firmware/whitted.s's";
  EXPECT_EQ(compiled.rays, assembly.rays);
  const double ratio = static_cast<double>(compiled.instructions) / static_cast<double>(assembly.instructions);
  RecordProperty("instruction_ratio", fmt::format("{:.3f}", ratio));
  if (GetParam().opt_level == 2 && GetParam().registers == 16) {
    EXPECT_LE(ratio, 1.3) << compiled.instructions << " instructions against the assembly's " << assembly.instructions;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, GlslWhitted,
                         testing::Values(Case{"cornell", "fp32"}, Case{"balls:2", "fp32"}, Case{"scenes/bunny.json", "fp32"},
                                         Case{"tetra:2", "fp32"}, Case{"cornell", "rpu24"}, Case{"balls:2", "rpu24"},
                                         Case{"cornell", "fp32", 0}, Case{"balls:2", "fp32", 0},
                                         Case{"cornell", "fp32", 2, 12}, Case{"balls:2", "fp32", 2, 12}),
                         [](const testing::TestParamInfo<Case>& i) {
                           std::string s = i.param.scene == "scenes/bunny.json" ? "bunny" : i.param.scene;
                           s = s.substr(0, s.find(':'));
                           return s + "_" + i.param.format + (i.param.opt_level == 0 ? "_O0" : "") +
                                  (i.param.registers != 16 ? fmt::format("_r{}", i.param.registers) : "");
                         });

// Spills (docs/shaders.md "Register allocation"): each library shader compiled for fewer
// registers than it uses, so that values wait on the memory stack, renders the image it
// renders in 16, bit for bit.
struct Spilled {
  std::string hit;
  int registers;
  friend void PrintTo(const Spilled& c, std::ostream* os) { *os << c.hit << " in " << c.registers; }
};

class GlslSpills : public testing::TestWithParam<Spilled> {};

TEST_P(GlslSpills, RenderWhatSixteenRegistersRender) {
  Scene scene = resolve_scene("cornell");
  for (Material& m : scene.materials) m.shader = GetParam().hit;
  const cc::Compiled& spilled = library(GetParam().hit, 2, GetParam().registers);
  std::size_t spills = 0;
  for (std::size_t at = 0; (at = spilled.listing.find(": spill", at)) != std::string::npos; ++at) ++spills;
  RecordProperty("spills", static_cast<int>(spills));
  EXPECT_GT(spills, 0u) << "nothing spilled: the case tests nothing";
  const Frame full = render(scene, library(GetParam().hit, 2, 16).firmware, fp::kFp32);
  const Frame few = render(scene, spilled.firmware, fp::kFp32);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < full.image.pixels.size(); ++i) {
    differ += std::memcmp(&full.image.pixels[i], &few.image.pixels[i], sizeof(glm::vec3)) != 0;
  }
  EXPECT_EQ(differ, 0u) << "pixels that differ from the 16-register image";
  RecordProperty("instruction_ratio", fmt::format("{:.3f}", static_cast<double>(few.instructions) /
                                                               static_cast<double>(full.instructions)));
}

INSTANTIATE_TEST_SUITE_P(Library, GlslSpills,
                         testing::Values(Spilled{"phong", 10}, Spilled{"mirror", 11},
                                         Spilled{"glossy", 10}, Spilled{"checker", 11}),
                         [](const testing::TestParamInfo<Spilled>& i) {
                           return fmt::format("{}_r{}", i.param.hit, i.param.registers);
                         });

}  // namespace
}  // namespace rpu
