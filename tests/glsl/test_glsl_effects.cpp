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
#include "reference/renderer.hpp"
#include "scene/resolve.hpp"
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

RenderSettings settings_of(int width, int height, int spp) {
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.max_depth = 2;
  return settings;
}

Image render_with(const Scene& scene, const isa::Firmware& fw, const RenderSettings& settings) {
  const spec::HardwareConfig& config = hardware_config("default");
  KdBuildConfig build = kd_build_config_for(std::string(config.name));
  build.format = fp::kFp32;
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const auto dev = device::make_functional_device(config, fp::kFp32);
  return device::render_frame(*dev, scene, si.image, fw, settings);
}

Image render_with(const Scene& scene, const isa::Firmware& fw, int width, int height) {
  return render_with(scene, fw, settings_of(width, height, 1));
}

// The library's Whitted at 64x48, one bounce.
Image render(const Scene& scene, int spp, std::uint32_t seed = 1) {
  RenderSettings settings = settings_of(64, 48, spp);
  settings.max_depth = 1;
  settings.seed = seed;
  return render_with(scene, firmware(), settings);
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
isa::Firmware library(std::initializer_list<const char*> hit_shaders, const char* raygen = "whitted") {
  const std::filesystem::path dir = RPU_GLSL_LIBRARY_DIR;
  std::vector<std::filesystem::path> files{dir / (std::string(raygen) + ".rgen")};
  for (const char* h : hit_shaders) files.push_back(dir / (std::string(h) + ".rchit"));
  files.push_back(dir / "background.rmiss");
  return cc::compile_files(files, {}).firmware;
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

// ---- glossy reflection ------------------------------------------------------------------
Material emitter(const std::string& name, glm::dvec3 color) {
  Material m;
  m.name = name;
  m.ambient = color;
  m.diffuse = glm::dvec3(0.0);
  m.shader = "phong";
  return m;
}

// A glossy floor seen from straight above, reflecting a small bright square that hangs
// over it behind the camera (so only its reflection is in the picture); no lights.
Scene glossy_scene(double roughness, const std::string& shader) {
  Scene s;
  s.source = "glossy floor";
  Material floor;
  floor.name = "floor";
  floor.diffuse = glm::dvec3(0.0);
  floor.reflectance = 1.0;
  floor.roughness = roughness;
  floor.shader = shader;
  s.materials = {floor, emitter("lamp", glm::dvec3(1.0))};
  quad(s, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20}, 0);
  quad(s, {-0.15f, 2, -0.15f}, {0.15f, 2, -0.15f}, {0.15f, 2, 0.15f}, {-0.15f, 2, 0.15f}, 1);
  s.camera.position = {0.0, 1.0, 0.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 0.0, -1.0};
  s.camera.vfov_degrees = 60.0;
  return s;
}

// The reflected square's spread: the brightness-weighted RMS distance of the pixels from
// the image centre, in pixels.
double spread(const Image& image) {
  double weight = 0.0, moment = 0.0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double v = image.pixels[static_cast<std::size_t>(y * image.width + x)].r;
      const double dx = x + 0.5 - image.width / 2.0, dy = y + 0.5 - image.height / 2.0;
      weight += v;
      moment += v * (dx * dx + dy * dy);
    }
  }
  return std::sqrt(moment / weight);
}

// Glossy highlights widen with roughness: the reflection of the square spreads further
// from its mirror image the rougher the floor; at roughness 0 it is the mirror's image.
TEST(GlslEffects, GlossyHighlightsWidenWithRoughness) {
  const isa::Firmware glossy = library({"glossy", "phong"});
  const RenderSettings settings = settings_of(48, 48, 16);
  const Image sharp = render_with(glossy_scene(0.0, "glossy"), glossy, settings);
  const double r0 = spread(sharp);
  const double r1 = spread(render_with(glossy_scene(0.1, "glossy"), glossy, settings));
  const double r2 = spread(render_with(glossy_scene(0.4, "glossy"), glossy, settings));
  RecordProperty("spread_pixels", fmt::format("roughness 0: {:.2f}, 0.1: {:.2f}, 0.4: {:.2f}", r0, r1, r2));
  EXPECT_GT(r1, 1.3 * r0) << r0 << " " << r1;
  EXPECT_GT(r2, 2.0 * r1) << r1 << " " << r2;
  const Image mirror = render_with(glossy_scene(0.0, "whitted"), library({"whitted", "phong"}), settings);
  EXPECT_LT(rms(sharp, mirror), 1e-3);
}

// ---- depth of field ---------------------------------------------------------------------
// A red square on the focal plane (5 from the camera) on the left, a green one three
// times as large and three times as far on the right, over black.
Scene lens_scene(double aperture) {
  Scene s;
  s.source = "two squares";
  s.materials = {emitter("red", {1.0, 0.0, 0.0}), emitter("green", {0.0, 1.0, 0.0})};
  quad(s, {-1.5f, -0.5f, 0}, {-0.5f, -0.5f, 0}, {-0.5f, 0.5f, 0}, {-1.5f, 0.5f, 0}, 0);
  quad(s, {1.5f, -1.5f, -10}, {4.5f, -1.5f, -10}, {4.5f, 1.5f, -10}, {1.5f, 1.5f, -10}, 1);
  s.camera.position = {0.0, 0.0, 5.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.vfov_degrees = 40.0;
  s.camera.aperture_radius = aperture;
  return s;
}

struct Blur {
  int focal = 0;  // pixels of the red square's (focal plane) colour that moved by more than 0.05
  int far = 0;    // the same for the green square's
};

Blur blur(const Image& lens, const Image& pinhole) {
  Blur b;
  for (std::size_t i = 0; i < lens.pixels.size(); ++i) {
    b.focal += std::abs(lens.pixels[i].r - pinhole.pixels[i].r) > 0.05f;
    b.far += std::abs(lens.pixels[i].g - pinhole.pixels[i].g) > 0.05f;
  }
  return b;
}

// Depth of field: the far square blurs more the larger the aperture, the square on the
// focal plane stays sharp, and at aperture 0 the thin lens is the pinhole, bit for bit.
TEST(GlslEffects, DepthOfFieldBlurGrowsWithApertureAndVanishesAtTheFocalPlane) {
  const isa::Firmware lens = library({"phong"}, "thin_lens");
  const RenderSettings settings = settings_of(64, 48, 16);
  const Image pinhole = render_with(lens_scene(0.0), library({"phong"}), settings);
  EXPECT_EQ(rms(render_with(lens_scene(0.0), lens, settings), pinhole), 0.0);
  const Blur small = blur(render_with(lens_scene(0.2), lens, settings), pinhole);
  const Blur large = blur(render_with(lens_scene(0.8), lens, settings), pinhole);
  RecordProperty("blurred_pixels", fmt::format("aperture 0.2: far {} focal {}, aperture 0.8: far {} focal {}",
                                                small.far, small.focal, large.far, large.focal));
  EXPECT_GT(small.far, 20);
  EXPECT_GT(large.far, 2 * small.far) << small.far << " " << large.far;
  EXPECT_LE(large.focal, 2) << "the square on the focal plane blurred";
}

// The thin lens follows the reference renderer's (same stream, same lens mapping).
TEST(GlslEffects, TheThinLensRendersTheReferencesImage) {
  Scene scene = resolve_scene("cornell");
  scene.camera.aperture_radius = 15.0;   // the box is 555 wide
  scene.camera.focus_distance = 1080.0;  // the middle of the box
  RenderSettings settings = settings_of(48, 36, 4);
  const Image reference = ReferenceRenderer(scene).render(settings);
  const Image lens = render_with(scene, library({"whitted"}, "thin_lens"), settings);
  const double psnr = psnr_srgb(reference, lens);
  Scene without_lens = scene;
  without_lens.camera.aperture_radius = 0.0;
  const double pinhole = psnr_srgb(reference, render_with(without_lens, library({"whitted"}, "thin_lens"), settings));
  RecordProperty("psnr_db", fmt::format("{:.1f}", psnr));
  RecordProperty("psnr_db_of_a_pinhole", fmt::format("{:.1f}", pinhole));
  EXPECT_GE(psnr, 40.0);
  EXPECT_LT(pinhole, 30.0) << "the lens made no difference";
}

// A pinhole firmware refuses a lens it would not model; the thin lens declares it models one.
TEST(GlslEffects, OnlyFirmwareWithAThinLensAcceptsAnAperture) {
  EXPECT_TRUE(library({"phong"}, "thin_lens").symbols.contains("FIRMWARE_THIN_LENS"));
  EXPECT_FALSE(library({"phong"}).symbols.contains("FIRMWARE_THIN_LENS"));
  try {
    render_with(lens_scene(0.2), library({"phong"}), settings_of(8, 6, 1));
    ADD_FAILURE() << "a pinhole firmware rendered a camera with an aperture";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the camera has a lens (aperture > 0) but the firmware renders a pinhole camera"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rpu
