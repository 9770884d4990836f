// Selected ray tracing (docs/selection.md) on the functional golden model with the
// built-in whitted.s: which pixels pass 1 traces and which it interpolates, checked
// pixel by pixel against a full frame and against the rule recomputed here from pass
// 0's framebuffer; the rays it saves; and the launches and selections it refuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "asm/assembler.hpp"
#include "asm/builtin_firmware.hpp"
#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "render/selection.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

namespace mm = spec::memory;

struct Fixture {
  Scene scene = resolve_scene("cornell");
  functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWoop);
  isa::Firmware firmware = isa::builtin_firmware("whitted.s");
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// Odd sizes, so that the last blocks are cut short by the frame's edge.
device::Launch small_launch(const Selection& select = {}) {
  device::Launch l{37, 27, 1, 2, 5};
  l.select = select;
  return l;
}

struct Frame {
  std::vector<glm::vec4> pixels;
  std::uint64_t rays = 0;
};

std::unique_ptr<device::Device> loaded_device(const isa::Firmware& firmware) {
  const Fixture& f = fixture();
  auto dev = device::make_functional_device(hardware_config("default"), fp::kFp32);
  dev->load_image(f.si.image.bytes, f.scene.source);
  dev->load_firmware(firmware, shader_names(f.scene));
  return dev;
}

Frame run(device::Device& dev, const device::Launch& launch) {
  dev.launch(launch);
  dev.wait();
  const functional::ShaderStats st = dev.stats().shader;
  return {dev.read_framebuffer(), st.closest_rays + st.any_rays};
}

Frame full_frame() {
  const auto dev = loaded_device(fixture().firmware);
  return run(*dev, small_launch());
}

// Pass 0 and pass 1 of a selected frame, launched by hand to keep pass 0's keys.
struct Passes {
  Frame corners, frame;
};

Passes selected_frame(const Selection& select) {
  const auto dev = loaded_device(fixture().firmware);
  device::Launch launch = small_launch(select);
  Passes p;
  p.corners = run(*dev, launch);
  launch.pass = 1;
  launch.corners = p.corners.pixels;
  p.frame = run(*dev, launch);
  return p;
}

bool same_rgb(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a, &b, 3 * sizeof(float)) == 0; }

std::uint32_t key_of(const glm::vec4& p) {
  std::uint32_t k;
  std::memcpy(&k, &p.w, sizeof k);
  return k;
}

struct Block {
  int x0, y0, x1, y1;
};

Block block_of(int x, int y, int width, int height, int b) {
  const int x0 = x / b * b, y0 = y / b * b;
  return {x0, y0, std::min(x0 + b, width - 1), std::min(y0 + b, height - 1)};
}

bool is_corner(int x, int y, int width, int height, int b) {
  return (x % b == 0 || x == width - 1) && (y % b == 0 || y == height - 1);
}

// What pass 1 does with a pixel that is no corner: counted per kind.
struct Verdicts {
  int interpolated = 0, traced = 0;
};

// Checks every pixel of a primitive-keyed selected frame: a corner is the full frame's
// pixel; any other pixel is traced (the full frame's, bit for bit) exactly when its
// block's corners hit different triangles or differ by more than the threshold in a
// channel, else it is the bilinear blend of the corners.
Verdicts check_primitive_frame(const Selection& select) {
  const Frame full = full_frame();
  const Passes p = selected_frame(select);
  const device::Launch l = small_launch();
  const int b = select.block;
  Verdicts v;
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      const std::size_t i = std::size_t(y) * l.width + x;
      const glm::vec4& got = p.frame.pixels[i];
      EXPECT_EQ(got.w, 1.0f) << "pixel " << x << "," << y;
      if (is_corner(x, y, l.width, l.height, b)) {
        EXPECT_TRUE(same_rgb(got, full.pixels[i])) << "corner " << x << "," << y;
        EXPECT_TRUE(same_rgb(p.corners.pixels[i], full.pixels[i])) << "pass 0 corner " << x << "," << y;
        continue;
      }
      const Block k = block_of(x, y, l.width, l.height, b);
      const glm::vec4 c[4] = {p.corners.pixels[std::size_t(k.y0) * l.width + k.x0],
                              p.corners.pixels[std::size_t(k.y1) * l.width + k.x0],
                              p.corners.pixels[std::size_t(k.y0) * l.width + k.x1],
                              p.corners.pixels[std::size_t(k.y1) * l.width + k.x1]};
      bool agree = true;
      for (const glm::vec4& corner : c) agree = agree && key_of(corner) == key_of(c[0]);
      for (int ch = 0; ch < 3; ++ch) {
        float lo = c[0][ch], hi = c[0][ch];
        for (const glm::vec4& corner : c) lo = std::min(lo, corner[ch]), hi = std::max(hi, corner[ch]);
        agree = agree && hi - lo <= select.threshold;
      }
      if (!agree) {
        ++v.traced;
        EXPECT_TRUE(same_rgb(got, full.pixels[i])) << "refined pixel " << x << "," << y;
        continue;
      }
      ++v.interpolated;
      const double tx = double(x - k.x0) / std::max(k.x1 - k.x0, 1);
      const double ty = double(y - k.y0) / std::max(k.y1 - k.y0, 1);
      for (int ch = 0; ch < 3; ++ch) {
        const double top = c[0][ch] + (c[2][ch] - double(c[0][ch])) * tx;
        const double bottom = c[1][ch] + (c[3][ch] - double(c[1][ch])) * tx;
        const double want = top + (bottom - top) * ty;
        EXPECT_NEAR(got[ch], want, 1e-5 * std::max(1.0, std::abs(want)))
            << "interpolated pixel " << x << "," << y << " channel " << ch;
      }
    }
  }
  return v;
}

TEST(SelectedRayTracing, TracesWhereTheCornersDisagreeAndInterpolatesElsewhere) {
  for (const int b : {2, 3, 4, 7}) {
    SCOPED_TRACE(testing::Message() << "block " << b);
    const Verdicts v = check_primitive_frame({b, 0.05f, mm::kSelectKeyPrimitive});
    // The frame has both kinds, so that the rule above was exercised both ways.
    EXPECT_GT(v.interpolated, 0);
    EXPECT_GT(v.traced, 0);
  }
}

TEST(SelectedRayTracing, ANegativeThresholdTracesEveryPixelAsTheFullFrameDoes) {
  const Frame full = full_frame();
  for (const int b : {2, 3, 4, int(mm::kSelectMaxBlock)}) {
    for (const std::uint32_t key : {mm::kSelectKeyMaterial, mm::kSelectKeyPrimitive}) {
      const Passes p = selected_frame({b, -1.0f, key});
      ASSERT_EQ(p.frame.pixels.size(), full.pixels.size());
      EXPECT_EQ(std::memcmp(p.frame.pixels.data(), full.pixels.data(), full.pixels.size() * sizeof(glm::vec4)), 0)
          << "block " << b;
      EXPECT_EQ(p.frame.rays, full.rays) << "block " << b;
    }
  }
}

TEST(SelectedRayTracing, SavesRays) {
  const std::uint64_t full = full_frame().rays;
  for (const int b : {2, 3, 4, 8}) {
    const std::uint64_t rays = selected_frame({b, 0.05f, mm::kSelectKeyMaterial}).frame.rays;
    EXPECT_LT(rays, full) << "block " << b;
  }
}

// A material key lets blocks across one material's triangles (the walls' halves)
// interpolate: never more rays than the primitive key, and on this scene fewer.
TEST(SelectedRayTracing, AMaterialKeyTracesNoMoreThanAPrimitiveKey) {
  const float no_colour_limit = std::numeric_limits<float>::max();
  const Passes material = selected_frame({4, no_colour_limit, mm::kSelectKeyMaterial});
  const Passes primitive = selected_frame({4, no_colour_limit, mm::kSelectKeyPrimitive});
  EXPECT_LT(material.frame.rays, primitive.frame.rays);
  const Frame full = full_frame();
  // Every pixel the material key traced, the primitive key traced too.
  for (std::size_t i = 0; i < full.pixels.size(); ++i) {
    if (same_rgb(material.frame.pixels[i], full.pixels[i]) && !same_rgb(primitive.frame.pixels[i], full.pixels[i])) {
      ADD_FAILURE() << "pixel " << i << " traced with the material key, interpolated with the primitive key";
    }
  }
}

TEST(SelectedRayTracing, RenderFrameRunsBothPasses) {
  const Fixture& f = fixture();
  const Selection select{3, 0.05f, mm::kSelectKeyMaterial};
  const Passes p = selected_frame(select);
  const auto dev = device::make_functional_device(hardware_config("default"), fp::kFp32);
  RenderSettings s;
  const device::Launch l = small_launch();
  s.width = l.width, s.height = l.height, s.spp = l.spp, s.max_depth = l.max_depth, s.seed = l.seed;
  s.select = select;
  const Image image = device::render_frame(*dev, f.scene, f.si.image, f.firmware, s);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    ASSERT_EQ(std::memcmp(&image.pixels[i], &p.frame.pixels[i], sizeof(glm::vec3)), 0) << "pixel " << i;
  }
  // The frame's statistics are both launches'.
  EXPECT_EQ(dev->stats().shader.closest_rays + dev->stats().shader.any_rays, p.frame.rays);
}

void expect_refused(device::Device& dev, const device::Launch& launch, const std::string& says) {
  try {
    dev.launch(launch);
    dev.wait();
    ADD_FAILURE() << "the launch was accepted; expected: " << says;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(SelectedRayTracing, RefusesFirmwareThatDoesNotSelect) {
  // whitted.s without its FIRMWARE_SELECTS constant: a frame that would silently trace
  // every pixel twice.
  std::string source = *isa::builtin_firmware_source("whitted.s");
  const std::string declaration = ".equ FIRMWARE_SELECTS, 1";
  const std::size_t at = source.find(declaration);
  ASSERT_NE(at, std::string::npos);
  source.erase(at, declaration.size());
  const isa::Firmware plain = isa::assemble("plain.s", [&](const std::filesystem::path& p) {
    return p == "plain.s" ? std::optional<std::string>(source) : isa::builtin_firmware_source(p);
  });
  const auto dev = loaded_device(plain);
  expect_refused(*dev, small_launch({2, 0.05f, mm::kSelectKeyMaterial}), "declares FIRMWARE_SELECTS");
  // Without selection it still renders.
  EXPECT_NO_THROW(run(*dev, small_launch()));
}

TEST(SelectedRayTracing, RefusesAPassOneWithoutItsPassZero) {
  const auto dev = loaded_device(fixture().firmware);
  device::Launch launch = small_launch({2, 0.05f, mm::kSelectKeyMaterial});
  launch.pass = 1;
  launch.corners.resize(std::size_t(launch.width) * launch.height);
  expect_refused(*dev, launch, "must follow its pass 0");
  launch.corners.pop_back();
  expect_refused(*dev, launch, "needs pass 0's framebuffer of 999 pixels, not 998");
  launch.pass = 2;
  expect_refused(*dev, launch, "selection pass 2 is neither 0 nor 1");
  device::Launch plain = small_launch();
  plain.pass = 1;
  expect_refused(*dev, plain, "a launch without selection has no pass 1");
  device::Launch big = small_launch({int(mm::kSelectMaxBlock) + 1, 0.05f, mm::kSelectKeyMaterial});
  expect_refused(*dev, big, "is larger than");
}

TEST(ParseSelection, ReadsEveryFormAndWritesItBack) {
  EXPECT_FALSE(parse_selection("1").enabled());
  EXPECT_EQ(to_string(parse_selection("1:0.3:primitive")), "1");
  const Selection a = parse_selection("4");
  EXPECT_EQ(a.block, 4);
  EXPECT_EQ(a.threshold, 0.05f);
  EXPECT_EQ(a.key, mm::kSelectKeyMaterial);
  const Selection b = parse_selection("3:0.125:primitive");
  EXPECT_EQ(b.block, 3);
  EXPECT_EQ(b.threshold, 0.125f);
  EXPECT_EQ(b.key, mm::kSelectKeyPrimitive);
  EXPECT_EQ(to_string(b), "3:0.125:primitive");
  EXPECT_EQ(to_string(parse_selection("2:-1")), "2:-1:material");
  for (const char* s : {"2", "16:0.05", "5:1e-3:material", "3:0.1:primitive"}) {
    const Selection once = parse_selection(s);
    const Selection twice = parse_selection(to_string(once));
    EXPECT_EQ(to_string(once), to_string(twice)) << s;
  }
}

TEST(ParseSelection, SaysWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "block '' is not a whole number"},
      {"x", "block 'x' is not a whole number"},
      {"2x", "block '2x' is not a whole number"},
      {"0", "block 0 is outside 1..16"},
      {"17", "block 17 is outside 1..16"},
      {"-2", "block -2 is outside 1..16"},
      {"2:", "threshold '' is not a finite number"},
      {"2:0.1x", "threshold '0.1x' is not a finite number"},
      {"2:inf", "threshold 'inf' is not a finite number"},
      {"2:nan", "threshold 'nan' is not a finite number"},
      {"2:1e99", "threshold '1e99' is not a finite number"},
      {"2:0.1:colour", "key 'colour' is neither material nor primitive"},
      {"2:0.1:material:x", "more than three parts"},
  };
  for (const auto& [text, says] : cases) {
    try {
      parse_selection(text);
      ADD_FAILURE() << "'" << text << "' was accepted";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(says), std::string::npos) << what;
      EXPECT_NE(what.find("docs/selection.md"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace rpu
