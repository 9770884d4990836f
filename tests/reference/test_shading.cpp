// The reference renderer's pixels equal the shading formula of docs/shading.md worked
// out by hand for scenes small enough to do so.
#include <gtest/gtest.h>

#include <cmath>

#include "reference/renderer.hpp"
#include "scene_builder.hpp"

namespace rpu {
namespace {

RenderSettings one_pixel(int max_depth = 5) {
  RenderSettings s;
  s.width = 1;
  s.height = 1;
  s.spp = 1;  // the pixel centre: the ray (0, 0, 5) -> (0, 0, -1)
  s.max_depth = max_depth;
  s.threads = 1;
  return s;
}

void expect_pixel(const Image& image, glm::dvec3 expected, double tolerance = 1e-6) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.at(0, 0)[c], expected[c], tolerance) << "channel " << c;
}

// One triangle in z = 0 facing the camera, one point light at (3, 0, 4).
// At the hit point P = 0: L = (3, 0, 4) / 5 = (0.6, 0, 0.8), N = (0, 0, 1), V = (0, 0, 1).
// N.L = 0.8; R = 2 (N.L) N - L = (-0.6, 0, 0.8); R.V = 0.8; (R.V)^10 = 0.1073741824.
// pixel = ka + light * (kd * 0.8 + ks * 0.1073741824)
//   r: 0.1 + 1.00 * (0.5 * 0.8 + 0.3 * 0.1073741824) = 0.53221225472
//   g: 0.1 + 0.50 * (0.6 * 0.8 + 0.3 * 0.1073741824) = 0.35610612736
//   b: 0.1 + 0.25 * (0.7 * 0.8 + 0.3 * 0.1073741824) = 0.24805306368
Scene one_triangle_one_light() {
  Scene scene;
  scene.camera = test::camera_down_z();
  Material m;
  m.ambient = {0.1, 0.1, 0.1};
  m.diffuse = {0.5, 0.6, 0.7};
  m.specular = {0.3, 0.3, 0.3};
  m.shininess = 10.0;
  const std::uint32_t id = test::add_material(scene, m);
  test::add_triangle(scene, {-10, -10, 0}, {10, -10, 0}, {0, 10, 0}, id);
  Light light;
  light.kind = LightKind::kPoint;
  light.position = {3.0, 0.0, 4.0};
  light.color = {1.0, 0.5, 0.25};
  scene.lights.push_back(light);
  return scene;
}

TEST(ReferenceShading, OneTriangleOneLightEqualsHandComputation) {
  const Scene scene = one_triangle_one_light();
  RayCounts counts;
  const Image image = ReferenceRenderer(scene).render(one_pixel(), &counts);
  expect_pixel(image, {0.53221225472, 0.35610612736, 0.24805306368});
  EXPECT_EQ(counts.primary, 1u);
  EXPECT_EQ(counts.shadow, 1u);
  EXPECT_EQ(counts.reflection + counts.refraction, 0u);
}

TEST(ReferenceShading, DirectionalLightUsesOnlyItsDirection) {
  Scene scene = one_triangle_one_light();
  scene.lights[0].kind = LightKind::kDirectional;
  scene.lights[0].direction = {-0.6, 0.0, -0.8};  // travelling towards -L of the point-light case
  const Image image = ReferenceRenderer(scene).render(one_pixel());
  expect_pixel(image, {0.53221225472, 0.35610612736, 0.24805306368});
}

TEST(ReferenceShading, BackFaceIsShadedWithTheNormalTurnedToTheViewer) {
  Scene scene = one_triangle_one_light();
  std::swap(scene.triangles[0].y, scene.triangles[0].z);  // now faces -z
  const Image image = ReferenceRenderer(scene).render(one_pixel());
  expect_pixel(image, {0.53221225472, 0.35610612736, 0.24805306368});
}

TEST(ReferenceShading, BlockedLightLeavesOnlyTheAmbientTerm) {
  Scene scene = one_triangle_one_light();
  // A small triangle halfway between P = 0 and the light at (3, 0, 4), off the camera ray.
  test::add_triangle(scene, {1.2f, -0.5f, 2.0f}, {1.8f, -0.5f, 2.0f}, {1.5f, 0.5f, 2.0f}, 0);
  const Image image = ReferenceRenderer(scene).render(one_pixel());
  expect_pixel(image, {0.1, 0.1, 0.1});
}

TEST(ReferenceShading, LightBehindTheSurfaceContributesNothingAndCastsNoRay) {
  Scene scene = one_triangle_one_light();
  scene.lights[0].position = {3.0, 0.0, -4.0};
  RayCounts counts;
  const Image image = ReferenceRenderer(scene).render(one_pixel(), &counts);
  expect_pixel(image, {0.1, 0.1, 0.1});
  EXPECT_EQ(counts.shadow, 0u);
}

TEST(ReferenceShading, AreaLightSamplesInsideItsRectangle) {
  Scene scene = one_triangle_one_light();
  // A 0-by-0 area light is a point light: the same pixel as the point light.
  scene.lights[0].kind = LightKind::kArea;
  scene.lights[0].edge_u = {0.0, 0.0, 0.0};
  scene.lights[0].edge_v = {0.0, 0.0, 0.0};
  expect_pixel(ReferenceRenderer(scene).render(one_pixel()), {0.53221225472, 0.35610612736, 0.24805306368});
  // A large area light far off to the side of a blocker is half blocked on average.
  Scene half = one_triangle_one_light();
  half.lights[0] = Light{LightKind::kArea, {1.0, 1.0, 1.0}, {-1.0, -1.0, 4.0}, {}, {2.0, 0.0, 0.0}, {0.0, 2.0, 0.0}};
  half.materials[0].specular = {0.0, 0.0, 0.0};
  half.materials[0].ambient = {0.0, 0.0, 0.0};
  // A blocker in z = 2 over x in [0.005, 3]: seen from P = 0 it hides the light points
  // with x >= 0.01, 49.5% of the light; it stays clear of the camera ray x = 0.
  test::add_triangle(half, {0.005f, -3.0f, 2.0f}, {3.0f, -3.0f, 2.0f}, {3.0f, 3.0f, 2.0f}, 0);
  test::add_triangle(half, {0.005f, -3.0f, 2.0f}, {3.0f, 3.0f, 2.0f}, {0.005f, 3.0f, 2.0f}, 0);
  half.camera.vfov_degrees = 1e-3;  // keep the jittered samples at P = 0
  RenderSettings s = one_pixel();
  s.spp = 4096;
  const Image image = ReferenceRenderer(half).render(s);
  // Unblocked light points (x < 0.01, 50.5% of the light) are 4 to sqrt(18) away, so
  // N.L lies in [4/sqrt(18), 1]: r = kd * 0.505 * mean(N.L), kd = 0.5, within noise.
  const double r = image.at(0, 0).r;
  EXPECT_GT(r, 0.5 * 0.505 * 4.0 / std::sqrt(18.0) - 0.02);
  EXPECT_LT(r, 0.5 * 0.505 + 0.02);
}

Scene mirror_below_camera(double reflectance) {
  Scene scene;
  scene.camera = test::camera_down_z();
  scene.background = {0.2, 0.4, 0.8};
  Material mirror;
  mirror.ambient = {0.1, 0.1, 0.1};
  mirror.diffuse = {0.0, 0.0, 0.0};
  mirror.reflectance = reflectance;
  test::add_square_z(scene, 10.0f, 0.0f, test::add_material(scene, mirror));
  return scene;
}

TEST(ReferenceShading, MirrorAddsReflectanceTimesWhatItSees) {
  // The reflected ray goes straight up and misses: pixel = ka + kr * background.
  const Image image = ReferenceRenderer(mirror_below_camera(0.5)).render(one_pixel());
  expect_pixel(image, {0.1 + 0.5 * 0.2, 0.1 + 0.5 * 0.4, 0.1 + 0.5 * 0.8});
}

TEST(ReferenceShading, MaxDepthZeroStopsReflection) {
  const Image image = ReferenceRenderer(mirror_below_camera(0.5)).render(one_pixel(0));
  expect_pixel(image, {0.1, 0.1, 0.1});
}

TEST(ReferenceShading, FacingMirrorsRecurseToMaxDepth) {
  // A second mirror above the camera, facing down: the ray bounces between the two.
  // Each hit adds ka = 0.1 and passes on kr = 0.5; after max_depth bounces the last hit
  // adds only ka: pixel = 0.1 * (1 + 0.5 + ... + 0.5^max_depth).
  Scene scene = mirror_below_camera(0.5);
  test::add_triangle(scene, {-10, -10, 10}, {10, 10, 10}, {10, -10, 10}, 0);
  test::add_triangle(scene, {-10, -10, 10}, {-10, 10, 10}, {10, 10, 10}, 0);
  for (int depth : {0, 1, 3, 6}) {
    double expected = 0.0;
    for (int k = 0; k <= depth; ++k) expected += 0.1 * std::pow(0.5, k);
    expect_pixel(ReferenceRenderer(scene).render(one_pixel(depth)), glm::dvec3(expected));
  }
}

Scene glass_slab(double transmittance, double ior) {
  Scene scene;
  scene.camera = test::camera_down_z();
  scene.background = {0.2, 0.4, 0.8};
  Material glass;
  glass.diffuse = {0.0, 0.0, 0.0};
  glass.transmittance = transmittance;
  glass.ior = ior;
  const std::uint32_t id = test::add_material(scene, glass);
  test::add_square_z(scene, 10.0f, 1.0f, id);   // top face, normal +z
  test::add_square_z(scene, 10.0f, -1.0f, id, true);  // bottom face, normal -z: a closed slab
  return scene;
}

TEST(ReferenceShading, PerpendicularRayPassesStraightThroughGlass) {
  // Entering and leaving at normal incidence bend nothing: pixel = kt^2 * background.
  RayCounts counts;
  const Image image = ReferenceRenderer(glass_slab(0.8, 1.5)).render(one_pixel(), &counts);
  expect_pixel(image, 0.64 * glm::dvec3(0.2, 0.4, 0.8));
  EXPECT_EQ(counts.refraction, 2u);
}

TEST(ReferenceShading, RefractionBendsByTheIndexOfRefraction) {
  // A ray at 45 degrees enters glass of ior sqrt(2): sin(theta_t) = sin(45)/sqrt(2) = 1/2,
  // so inside it travels at 30 degrees and exits back at 45 degrees, parallel to itself,
  // displaced. A mirror floor below the slab tells where it went: a black tile under the
  // undisplaced path and a white one under the displaced path.
  Scene scene = glass_slab(1.0, std::sqrt(2.0));
  scene.background = {0.0, 0.0, 0.0};
  Material white;
  white.ambient = {1.0, 1.0, 1.0};
  white.diffuse = {0.0, 0.0, 0.0};
  Material black;
  black.ambient = {0.0, 0.0, 0.0};
  black.diffuse = {0.0, 0.0, 0.0};
  const std::uint32_t w = test::add_material(scene, white), b = test::add_material(scene, black);
  // Camera at (0, 0, 3) looking along (1, 0, -1)/sqrt2: hits the top face z = 1 at x = 2.
  scene.camera.position = {0.0, 0.0, 3.0};
  scene.camera.look_at = {1.0, 0.0, 2.0};
  // Inside, 2 units of depth at 30 degrees move x by 2 tan(30) = 1.1547 -> exits at
  // x = 3.1547, then reaches the floor z = -3 at x = 5.1547 (undisplaced: x = 6).
  test::add_triangle(scene, {4.8f, -5, -3}, {5.5f, -5, -3}, {5.5f, 5, -3}, w);
  test::add_triangle(scene, {4.8f, -5, -3}, {5.5f, 5, -3}, {4.8f, 5, -3}, w);
  test::add_triangle(scene, {5.7f, -5, -3}, {6.3f, -5, -3}, {6.3f, 5, -3}, b);
  test::add_triangle(scene, {5.7f, -5, -3}, {6.3f, 5, -3}, {5.7f, 5, -3}, b);
  expect_pixel(ReferenceRenderer(scene).render(one_pixel()), {1.0, 1.0, 1.0});
}

TEST(ReferenceShading, TotalInternalReflectionReflectsTheTransmittedWeight) {
  // Inside glass of ior 2 a ray meeting the surface at 45 degrees (> asin(1/2) = 30) is
  // totally reflected. The camera sits inside the slab, looking up at 45 degrees; the
  // reflected ray heads down to the bottom face, is reflected again... each face turns
  // the ray back, so nothing reaches the background: pixel = 0.
  Scene scene = glass_slab(1.0, 2.0);
  scene.camera.position = {0.0, 0.0, 0.0};
  scene.camera.look_at = {1.0, 0.0, 1.0};
  RayCounts counts;
  const Image image = ReferenceRenderer(scene).render(one_pixel(4), &counts);
  expect_pixel(image, {0.0, 0.0, 0.0});
  EXPECT_EQ(counts.refraction, 0u);
  EXPECT_EQ(counts.reflection, 4u);
  // Below the critical angle the ray leaves: looking nearly straight up reaches the sky.
  scene.camera.look_at = {0.1, 0.0, 1.0};
  const Image out = ReferenceRenderer(scene).render(one_pixel(4));
  expect_pixel(out, {0.2, 0.4, 0.8});
}

TEST(ReferenceShading, ImageDoesNotDependOnThreadCount) {
  Scene scene = one_triangle_one_light();
  scene.lights[0] = Light{LightKind::kArea, {1.0, 1.0, 1.0}, {-1.0, -1.0, 4.0}, {}, {2.0, 0.0, 0.0}, {0.0, 2.0, 0.0}};
  test::add_triangle(scene, {0.005f, -3.0f, 2.0f}, {3.0f, -3.0f, 2.0f}, {3.0f, 3.0f, 2.0f}, 0);
  RenderSettings s;
  s.width = 61;
  s.height = 37;
  s.spp = 5;
  const ReferenceRenderer renderer(scene);
  s.threads = 1;
  const Image one = renderer.render(s);
  s.threads = 3;
  const Image three = renderer.render(s);
  EXPECT_EQ(one.pixels, three.pixels);
}

}  // namespace
}  // namespace rpu
