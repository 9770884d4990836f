// Every structure against brute force on five scenes of different character, at least
// 10^5 rays each (docs/accel.md, "Tests").
#include <gtest/gtest.h>

#include "agreement.hpp"

namespace rpu::accel::test {
namespace {

class StructuresAgreeWithBruteForce : public ::testing::TestWithParam<AgreementCase> {};

TEST_P(StructuresAgreeWithBruteForce, OnPrimaryShadowAndRandomRays) { expect_agreement(GetParam()); }

INSTANTIATE_TEST_SUITE_P(
    Scenes, StructuresAgreeWithBruteForce,
    ::testing::Values(AgreementCase{"cornell", [] { return scene_named("cornell"); }, 256, 256, 40000, 100000},
                      AgreementCase{"balls1", [] { return scene_named("balls:1"); }, 160, 160, 40000, 100000},
                      AgreementCase{"bunny", [] { return scene_named("scenes/bunny.json"); }, 160, 160, 40000,
                                    100000},
                      AgreementCase{"tetra6", [] { return scene_named("tetra:6"); }, 256, 256, 40000, 100000},
                      AgreementCase{"teapot_in_a_stadium", teapot_in_a_stadium, 200, 200, 40000, 100000},
                      AgreementCase{"scattered", [] { return scattered_triangles(3000, 5); }, 256, 256, 40000,
                                    100000}),
    [](const ::testing::TestParamInfo<AgreementCase>& param) { return param.param.name; });

}  // namespace
}  // namespace rpu::accel::test
