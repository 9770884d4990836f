// Every structure against brute force on the larger scenes, whose brute force takes
// longer than CI's budget (label slow: ctest --preset slow).
#include <gtest/gtest.h>

#include "agreement.hpp"

namespace rpu::accel::test {
namespace {

class StructuresAgreeWithBruteForceOnLargeScenes : public ::testing::TestWithParam<AgreementCase> {};

TEST_P(StructuresAgreeWithBruteForceOnLargeScenes, OnPrimaryShadowAndRandomRays) { expect_agreement(GetParam()); }

INSTANTIATE_TEST_SUITE_P(
    Scenes, StructuresAgreeWithBruteForceOnLargeScenes,
    ::testing::Values(AgreementCase{"balls2", [] { return scene_named("balls:2"); }, 256, 256, 40000, 100000},
                      AgreementCase{"tetra7", [] { return scene_named("tetra:7"); }, 256, 256, 40000, 100000}),
    [](const ::testing::TestParamInfo<AgreementCase>& param) { return param.param.name; });

}  // namespace
}  // namespace rpu::accel::test
