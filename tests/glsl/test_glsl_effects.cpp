// The shader library's distributed effects on the functional device (docs/shaders.md
// "The library"): each test measures the effect and would fail without it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "cc/compiler.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/scene.hpp"

namespace rpu {
namespace {

const isa::Firmware& firmware() {
  static const isa::Firmware fw = [] {
    const std::filesystem::path dir = RPU_GLSL_LIBRARY_DIR;
    return cc::compile_files({dir / "whitted.rgen", dir / "whitted.rchit", dir / "background.rmiss"}, {}).firmware;
  }();
  return fw;
}

void quad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, std::uint32_t material) {
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  s.positions.insert(s.positions.end(), {a, b, c, d});
  s.triangles.push_back({base, base + 1, base + 2});
  s.triangles.push_back({base, base + 2, base + 3});
  s.material_ids.insert(s.material_ids.end(), {material, material});
}

// A floor, a small square floating over it, and one light above the square: an area light
// of side `light_size`, or a point light if 0. Seen from low over the floor.
Scene shadow_scene(double light_size, bool occluder) {
  Scene s;
  s.source = "shadow scene";
  s.background = {0.0, 0.0, 1.0};
  Material floor;
  floor.name = "floor";
  floor.diffuse = glm::dvec3(0.8);
  s.materials.push_back(floor);
  quad(s, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, 0);
  if (occluder) quad(s, {-0.5f, 1, -2.5f}, {0.5f, 1, -2.5f}, {0.5f, 1, -3.5f}, {-0.5f, 1, -3.5f}, 0);
  Light light;
  light.color = glm::dvec3(1.0);
  if (light_size > 0.0) {
    light.kind = LightKind::kArea;
    light.position = {-light_size / 2, 3.0, -3.0 - light_size / 2};
    light.edge_u = {light_size, 0.0, 0.0};
    light.edge_v = {0.0, 0.0, light_size};
  } else {
    light.kind = LightKind::kPoint;
    light.position = {0.0, 3.0, -3.0};
  }
  s.lights.push_back(light);
  s.camera.position = {0.0, 1.6, 3.0};
  s.camera.look_at = {0.0, 0.3, -3.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.vfov_degrees = 40.0;
  return s;
}

Image render(const Scene& scene, int spp, std::uint32_t seed = 1) {
  const spec::HardwareConfig& config = hardware_config("default");
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  build.format = fp::kFp32;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const auto dev = device::make_functional_device(config, fp::kFp32);
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.spp = spp;
  settings.max_depth = 1;
  settings.seed = seed;
  return device::render_frame(*dev, scene, si.image, firmware(), settings);
}

// Pixels of the floor in partial shadow: lit by more than 5% and less than 95% of the
// light the same pixel gets without the occluder (the samples draw the same light points).
int penumbra_pixels(double light_size) {
  const Image shadowed = render(shadow_scene(light_size, true), 16);
  const Image open = render(shadow_scene(light_size, false), 16);
  int count = 0;
  for (std::size_t i = 0; i < shadowed.pixels.size(); ++i) {
    const float lit = open.pixels[i].r;
    if (open.pixels[i].b != lit || lit <= 0.0f) continue;  // background (blue) or unlit
    const float v = shadowed.pixels[i].r / lit;
    count += v > 0.05f && v < 0.95f;
  }
  return count;
}

// Soft shadows: the penumbra widens with the area light's size; a point light (or an
// area light sampled at one fixed point) has next to none.
TEST(GlslEffects, PenumbraWidthGrowsWithTheAreaLightsSize) {
  const int point = penumbra_pixels(0.0);
  const int small = penumbra_pixels(0.3);
  const int large = penumbra_pixels(1.5);
  RecordProperty("penumbra_pixels", fmt::format("point {}, side 0.3: {}, side 1.5: {}", point, small, large));
  EXPECT_GT(small, point);
  EXPECT_GT(large, 2 * small) << "point " << point << ", small " << small << ", large " << large;
}

double rms(const Image& a, const Image& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const glm::vec3 d = a.pixels[i] - b.pixels[i];
    sum += static_cast<double>(glm::dot(d, d));
  }
  return std::sqrt(sum / static_cast<double>(a.pixels.size()));
}

// Anti-aliasing: 16 jittered samples a pixel land nearer a 256-sample reference than one
// sample at the pixel's centre does (the error is all at edges: the scene's light is a point).
TEST(GlslEffects, AntiAliasingLowersTheErrorAgainstA256SampleReference) {
  const Scene scene = shadow_scene(0.0, true);
  const Image reference = render(scene, 256, 7);
  const double one = rms(render(scene, 1), reference);
  const double sixteen = rms(render(scene, 16), reference);
  RecordProperty("rms", fmt::format("1 spp {:.5f}, 16 spp {:.5f}", one, sixteen));
  EXPECT_LT(sixteen, 0.5 * one) << "1 spp " << one << ", 16 spp " << sixteen;
}

// ---- the library's materials -------------------------------------------------------------
isa::Firmware library(std::initializer_list<const char*> hit_shaders) {
  const std::filesystem::path dir = RPU_GLSL_LIBRARY_DIR;
  std::vector<std::filesystem::path> files{dir / "whitted.rgen"};
  for (const char* h : hit_shaders) files.push_back(dir / (std::string(h) + ".rchit"));
  files.push_back(dir / "background.rmiss");
  return cc::compile_files(files, {}).firmware;
}

Image render_with(const Scene& scene, const isa::Firmware& fw, int width, int height) {
  const spec::HardwareConfig& config = hardware_config("default");
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const auto dev = device::make_functional_device(config, fp::kFp32);
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = 1;
  settings.max_depth = 2;
  return device::render_frame(*dev, scene, si.image, fw, settings);
}

Scene with_floor_shader(const std::string& shader) {
  Scene s = shadow_scene(0.0, true);
  s.materials[0].shader = shader;
  s.materials[0].specular = glm::dvec3(0.5);
  s.materials[0].shininess = 8.0;
  return s;
}

// Phong is Whitted without secondary rays: on a scene without reflection or
// transmission the two give the same image.
TEST(GlslLibrary, PhongIsWhittedWithoutSecondaryRays) {
  const Image phong = render_with(with_floor_shader("phong"), library({"phong"}), 64, 48);
  const Image whitted = render_with(with_floor_shader("whitted"), library({"whitted"}), 64, 48);
  EXPECT_EQ(rms(phong, whitted), 0.0);
}

// The checker texture: floor pixels are Phong's or a fifth of it, and both occur.
TEST(GlslLibrary, TheCheckerAlternatesTheDiffuseColourAndAFifthOfIt) {
  Scene checker = with_floor_shader("checker");
  Scene phong = with_floor_shader("phong");
  checker.materials[0].specular = phong.materials[0].specular = glm::dvec3(0.0);
  const Image c = render_with(checker, library({"checker"}), 64, 48);
  const Image p = render_with(phong, library({"phong"}), 64, 48);
  int full = 0, fifth = 0, other = 0;
  for (std::size_t i = 0; i < c.pixels.size(); ++i) {
    if (p.pixels[i].r <= 0.0f || p.pixels[i].b != p.pixels[i].r) continue;  // background, shadow
    const float ratio = c.pixels[i].r / p.pixels[i].r;
    if (std::abs(ratio - 1.0f) < 1e-5f) {
      ++full;
    } else if (std::abs(ratio - 0.2f) < 1e-5f) {
      ++fifth;
    } else {
      ++other;
    }
  }
  EXPECT_GT(full, 100);
  EXPECT_GT(fifth, 100);
  EXPECT_EQ(other, 0);
}

// A mirror floor shows the sky (the blue background) where Phong's floor is grey.
TEST(GlslLibrary, AMirrorReflectsTheSky) {
  const Image mirror = render_with(with_floor_shader("mirror"), library({"mirror"}), 64, 48);
  const Image phong = render_with(with_floor_shader("phong"), library({"phong"}), 64, 48);
  int reflecting = 0;
  for (std::size_t i = 0; i < mirror.pixels.size(); ++i) {
    const bool floor = phong.pixels[i].r > 0.0f && phong.pixels[i].b == phong.pixels[i].r;
    reflecting += floor && mirror.pixels[i].b > mirror.pixels[i].r + 0.2f;
  }
  EXPECT_GT(reflecting, 100);
}

// Fresnel: a glass plate over a black floor under a white sky, seen along one direction:
// the pixel is the reflected fraction, Schlick's R0 = 0.04 at normal incidence (ior 1.5)
// and more toward grazing: 0.04 + 0.96 (1 - cos 75 deg)^5 = 0.2343.
TEST(GlslLibrary, GlassReflectsTheFresnelFraction) {
  const auto reflected = [](double angle_degrees) {
    Scene s;
    s.source = "glass plate";
    s.background = glm::dvec3(1.0);
    Material glass;
    glass.name = "glass";
    glass.diffuse = glm::dvec3(1.0);
    glass.ior = 1.5;
    glass.shader = "glass";
    Material black;
    black.name = "black";
    black.diffuse = glm::dvec3(0.0);
    black.shader = "phong";
    s.materials = {glass, black};
    quad(s, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, 0);
    quad(s, {-50, -1, 50}, {50, -1, 50}, {50, -1, -50}, {-50, -1, -50}, 1);
    const double a = angle_degrees * 3.14159265358979 / 180.0;
    s.camera.position = {0.0, 2.0 * std::cos(a), 2.0 * std::sin(a)};
    s.camera.look_at = {0.0, 0.0, 0.0};
    s.camera.up = std::abs(angle_degrees) < 1.0 ? glm::dvec3(0.0, 0.0, -1.0) : glm::dvec3(0.0, 1.0, 0.0);
    s.camera.vfov_degrees = 1.0;
    return render_with(s, library({"glass", "phong"}), 1, 1).pixels[0].r;
  };
  EXPECT_NEAR(reflected(0.0), 0.04, 1e-4);
  EXPECT_NEAR(reflected(75.0), 0.04 + 0.96 * std::pow(1.0 - std::cos(75.0 * 3.14159265358979 / 180.0), 5.0), 1e-3);
}

}  // namespace
}  // namespace rpu
