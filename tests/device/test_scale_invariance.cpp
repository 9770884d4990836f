// A mesh scaled by 2^k renders the same image, bit for bit, for every k in [-60, 60]:
// on the reference renderer and on the functional golden model in several number
// formats, through the mesh loader, the default camera and light, and a scene file's
// transform. Every tolerance (vertex welding, degeneracy, ray epsilons, the camera's
// framing) is relative to the scene's own size; the chip renders the scene moved into
// its kd space (functional::chip_space_scene).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "reference/renderer.hpp"
#include "scene/mesh.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"
#include "scene/scene_file.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

constexpr int kMinExponent = -60, kMaxExponent = 60;

// A binary little-endian PLY of `geometry`'s triangles with every coordinate x 2^k:
// binary fp32 keeps the scaled values exact, as a decimal text format would not.
fs::path write_scaled_ply(const Scene& geometry, int k, const fs::path& dir) {
  const fs::path path = dir / fmt::format("mesh_2e{}.ply", k);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << "ply\nformat binary_little_endian 1.0\n"
      << "element vertex " << geometry.positions.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << geometry.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const glm::vec3& p : geometry.positions) {
    for (int c = 0; c < 3; ++c) {
      const float v = std::ldexp(p[c], k);
      out.write(reinterpret_cast<const char*>(&v), sizeof v);
    }
  }
  for (const glm::uvec3& t : geometry.triangles) {
    const char three = 3;
    out.write(&three, 1);
    for (int c = 0; c < 3; ++c) {
      const auto index = static_cast<std::int32_t>(t[c]);
      out.write(reinterpret_cast<const char*>(&index), sizeof index);
    }
  }
  out.close();
  EXPECT_TRUE(out) << path;
  return path;
}

RenderSettings small_frame() {
  RenderSettings s;
  s.width = 24;
  s.height = 18;
  s.spp = 1;
  s.max_depth = 2;
  s.threads = 1;
  return s;
}

Image render_reference(const Scene& scene) { return ReferenceRenderer(scene).render(small_frame()); }

Image render_functional(const Scene& world, const std::string& format) {
  const fp::Format f = fp::format_by_name(format);
  KdBuildConfig build = kd_build_config_for("default");
  build.format = f;
  const Scene scene = functional::chip_space_scene(world, f);
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  device::FunctionalOptions options;
  options.host_threads = 1;
  const auto dev = device::make_functional_device(hardware_config("default"), f, options);
  return device::render_frame(*dev, scene, si.image, isa::builtin_firmware("whitted.s"), small_frame());
}

// The first differing pixel, or "" when the images are equal bit for bit.
std::string first_difference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return "the sizes differ";
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    if (std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(glm::vec3)) != 0) {
      return fmt::format("pixel ({}, {}): ({}, {}, {}) vs ({}, {}, {})", i % a.width, i / a.width, a.pixels[i].x,
                         a.pixels[i].y, a.pixels[i].z, b.pixels[i].x, b.pixels[i].y, b.pixels[i].z);
    }
  }
  return "";
}

bool lit(const Image& image, const Scene& scene) {
  for (const glm::vec3& p : image.pixels) {
    if (glm::dvec3(p) != scene.background) return true;
  }
  return false;
}

class ScaleInvariance : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / fmt::format("rpu_scale_{}", ::getpid());
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path ScaleInvariance::dir_;

// The sphereflake's spheres share vertices (welding), sit on a floor (shadow-ray
// epsilons) and mirror each other (secondary-ray epsilons).
TEST_F(ScaleInvariance, BareMeshRendersTheSameAtEveryPowerOfTwoScale) {
  const Scene geometry = make_sphereflake(1, 8);
  const Scene unit = load_bare_mesh(write_scaled_ply(geometry, 0, dir_));
  const Image reference = render_reference(unit);
  const Image fp32 = render_functional(unit, "fp32");
  ASSERT_TRUE(lit(reference, unit));
  ASSERT_TRUE(lit(fp32, unit));
  for (int k = kMinExponent; k <= kMaxExponent; ++k) {
    const Scene scaled = load_bare_mesh(write_scaled_ply(geometry, k, dir_));
    ASSERT_EQ(scaled.triangles.size(), unit.triangles.size()) << "k = " << k;
    EXPECT_EQ(first_difference(reference, render_reference(scaled)), "") << "reference, k = " << k;
    EXPECT_EQ(first_difference(fp32, render_functional(scaled, "fp32")), "") << "functional fp32, k = " << k;
  }
}

// Narrow formats cannot hold the world's coordinates at most scales; the chip's space can.
TEST_F(ScaleInvariance, NarrowFormatsRenderTheSameAtEveryPowerOfTwoScale) {
  const Scene geometry = make_sphereflake(1, 8);
  const Scene unit = load_bare_mesh(write_scaled_ply(geometry, 0, dir_));
  for (const std::string format : {"rpu24", "fp16"}) {
    const Image at_unit = render_functional(unit, format);
    ASSERT_TRUE(lit(at_unit, unit)) << format;
    for (int k = kMinExponent; k <= kMaxExponent; k += 7) {
      const Scene scaled = load_bare_mesh(write_scaled_ply(geometry, k, dir_));
      EXPECT_EQ(first_difference(at_unit, render_functional(scaled, format)), "") << format << ", k = " << k;
    }
  }
}

// A whole scene file scaled by its mesh's transform, camera and light with it; smooth
// normals generated by the loader.
TEST_F(ScaleInvariance, SceneFileWithATransformRendersTheSameAtEveryPowerOfTwoScale) {
  const fs::path mesh = write_scaled_ply(make_sphereflake(1, 8), 0, dir_);
  const auto scene_at = [&](int k) {
    const double s = std::ldexp(1.0, k);
    const std::string json = fmt::format(
        R"({{"camera": {{"position": [{0}, {1}, {2}], "look_at": [0, 0, 0], "up": [0, 0, 1], "vfov": 40}},
            "lights": [{{"type": "point", "position": [{3}, {4}, {5}]}}],
            "meshes": [{{"file": "{6}", "smooth": true,
                         "transform": [[{7}, 0, 0, 0], [0, {7}, 0, 0], [0, 0, {7}, 0], [0, 0, 0, 1]]}}]}})",
        2.1 * s, 1.3 * s, 1.7 * s, 4.0 * s, 3.0 * s, 2.0 * s, mesh.filename().string(), s);
    return parse_scene_json(json, dir_, fmt::format("scaled_2e{}.json", k));
  };
  const Scene unit = scene_at(0);
  const Image reference = render_reference(unit);
  const Image fp32 = render_functional(unit, "fp32");
  ASSERT_TRUE(lit(reference, unit));
  for (int k = kMinExponent; k <= kMaxExponent; ++k) {
    const Scene scaled = scene_at(k);
    EXPECT_EQ(first_difference(reference, render_reference(scaled)), "") << "reference, k = " << k;
    EXPECT_EQ(first_difference(fp32, render_functional(scaled, "fp32")), "") << "functional fp32, k = " << k;
  }
}

// One triangle of any size is a triangle: nothing about it is "too small".
TEST_F(ScaleInvariance, ATinyTriangleIsKept) {
  Scene one;
  one.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  one.triangles = {{0, 1, 2}};
  for (const int k : {-60, -40, -17, 0}) {
    const Scene s = load_bare_mesh(write_scaled_ply(one, k, dir_));
    EXPECT_EQ(s.triangles.size(), 1u) << "k = " << k;
    EXPECT_TRUE(lit(render_reference(s), s)) << "k = " << k;
  }
}

}  // namespace
}  // namespace rpu
