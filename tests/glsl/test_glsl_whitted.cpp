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

const isa::Firmware& glsl_whitted(int opt_level) {
  static std::map<int, isa::Firmware> compiled;
  if (!compiled.count(opt_level)) {
    const std::filesystem::path dir = RPU_GLSL_LIBRARY_DIR;
    cc::CompileOptions options;
    options.opt_level = opt_level;
    compiled[opt_level] =
        cc::compile_files({dir / "whitted.rgen", dir / "whitted.rchit", dir / "background.rmiss"}, options).firmware;
  }
  return compiled[opt_level];
}

struct Case {
  std::string scene;
  std::string format;
  int opt_level = 2;
  friend void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << " " << c.format << " -O" << c.opt_level; }
};

class GlslWhitted : public testing::TestWithParam<Case> {};

// Issue 18: the GLSL Whitted renders the test scenes as the assembly does (the goal:
// identical images), at -O2 with at most 1.3x its instructions (at -O0 the ratio is
// only recorded).
TEST_P(GlslWhitted, RendersTheAssemblysImageWithin1_3xItsInstructions) {
  const Scene scene = resolve_scene(GetParam().scene);
  const fp::Format format = fp::format_by_name(GetParam().format);
  const Frame assembly = render(scene, isa::builtin_firmware("whitted.s"), format);
  const Frame compiled = render(scene, glsl_whitted(GetParam().opt_level), format);
  ASSERT_EQ(compiled.image.pixels.size(), assembly.image.pixels.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < compiled.image.pixels.size(); ++i) {
    differ += std::memcmp(&compiled.image.pixels[i], &assembly.image.pixels[i], sizeof(glm::vec3)) != 0;
  }
  EXPECT_EQ(differ, 0u) << "pixels that differ from firmware/whitted.s's";
  EXPECT_EQ(compiled.rays, assembly.rays);
  const double ratio = static_cast<double>(compiled.instructions) / static_cast<double>(assembly.instructions);
  RecordProperty("instruction_ratio", fmt::format("{:.3f}", ratio));
  if (GetParam().opt_level == 2) {
    EXPECT_LE(ratio, 1.3) << compiled.instructions << " instructions against the assembly's " << assembly.instructions;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, GlslWhitted,
                         testing::Values(Case{"cornell", "fp32"}, Case{"balls:2", "fp32"}, Case{"scenes/bunny.json", "fp32"},
                                         Case{"tetra:2", "fp32"}, Case{"cornell", "rpu24"}, Case{"balls:2", "rpu24"},
                                         Case{"cornell", "fp32", 0}, Case{"balls:2", "fp32", 0}),
                         [](const testing::TestParamInfo<Case>& i) {
                           std::string s = i.param.scene == "scenes/bunny.json" ? "bunny" : i.param.scene;
                           s = s.substr(0, s.find(':'));
                           return s + "_" + i.param.format + (i.param.opt_level == 0 ? "_O0" : "");
                         });

}  // namespace
}  // namespace rpu
