// Every structure against brute force on six scenes of different character, at least
// 10^5 rays each (docs/accel.md, "Tests"): images just large enough for that, to keep
// CI's time.
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/brute_force.hpp"
#include "accel/structure.hpp"
#include "agreement.hpp"
#include "common/random_vector.hpp"

namespace rpu::accel::test {
namespace {

class StructuresAgreeWithBruteForce : public ::testing::TestWithParam<AgreementCase> {};

TEST_P(StructuresAgreeWithBruteForce, OnPrimaryShadowAndRandomRays) { expect_agreement(GetParam()); }

INSTANTIATE_TEST_SUITE_P(
    Scenes, StructuresAgreeWithBruteForce,
    ::testing::Values(AgreementCase{"cornell", [] { return scene_named("cornell"); }, 200, 200, 40000, 100000},
                      AgreementCase{"balls1", [] { return scene_named("balls:1"); }, 140, 140, 40000, 100000},
                      AgreementCase{"bunny", [] { return scene_named("scenes/bunny.json"); }, 160, 160, 40000,
                                    100000},
                      AgreementCase{"tetra6", [] { return scene_named("tetra:6"); }, 240, 240, 40000, 100000},
                      AgreementCase{"stadium", [] { return scene_named("stadium:5"); }, 190, 190, 40000, 100000},
                      AgreementCase{"scattered", [] { return scene_named("scattered:3000"); }, 240, 240, 40000,
                                    100000}),
    [](const ::testing::TestParamInfo<AgreementCase>& param) { return param.param.name; });

}  // namespace
}  // namespace rpu::accel::test

namespace rpu::accel::test {
namespace {

// Rays that skim a triangle's plane at a small angle, from a random point of a random
// triangle: the case the structures' padded boxes are there for (docs/accel.md,
// "Padded boxes"). A ray lying in the plane itself (angle 0) meets it at a t that
// rounding decides; it is not asked to agree.
TEST(StructuresAgreeWithBruteForceOn, RaysGrazingATrianglesPlane) {
  for (const char* name : {"cornell", "scenes/bunny.json", "balls:1"}) {
    const Scene scene = scene_named(name);
    const TriangleSet triangles(scene);
    const BruteForce brute(triangles);
    std::vector<std::unique_ptr<Structure>> structures;
    for (const std::string& structure : structure_names()) {
      if (structure != "brute") structures.push_back(build_structure(structure, triangles, {}));
    }
    const double back = 0.3 * glm::length(triangles.bounds().hi - triangles.bounds().lo);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> unit(0.0, 1.0), symmetric(-1.0, 1.0);
    for (const double angle : {1e-3, 1e-6, 1e-8, 1e-10}) {
      for (int i = 0; i < 5000; ++i) {
        const Triangle& t = triangles.triangles()[rng() % triangles.size()];
        const glm::dvec3 normal = glm::normalize(glm::cross(t.e1, t.e2));
        const double a = unit(rng);
        const double b = unit(rng);
        const glm::dvec3 on = t.v0 + (a * (1.0 - b)) * t.e1 + (a * b) * t.e2;
        const glm::dvec3 along = glm::normalize(glm::cross(normal, random_vector(symmetric, rng)));
        const glm::dvec3 d = glm::normalize(along + angle * normal);
        const Ray r{on - back * d, d};
        RayCost cost;
        const Hit expected = brute.closest_hit(r, cost);
        for (const auto& s : structures) {
          const Hit got = s->closest_hit(r, cost);
          ASSERT_EQ(got.prim, expected.prim) << name << " " << s->name() << " angle " << angle << " ray " << i;
          ASSERT_EQ(got.t, expected.t) << name << " " << s->name() << " angle " << angle << " ray " << i;
          ASSERT_EQ(s->any_hit(r, cost), expected.hit()) << name << " " << s->name() << " angle " << angle;
        }
      }
    }
  }
}

}  // namespace
}  // namespace rpu::accel::test
