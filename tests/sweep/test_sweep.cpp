// The sweep file's expansion and errors, and the ray checks a sweep point runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "fp/format.hpp"
#include "scene/procedural.hpp"
#include "sweep/area.hpp"
#include "sweep/ray_checks.hpp"
#include "sweep/sweep_spec.hpp"
#include "trace_fixtures.hpp"

namespace rpu::sweep {
namespace {

Spec parse(const std::string& text) { return parse_spec(text, "test.toml", std::filesystem::current_path()); }

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(SweepSpec, TheGridIsEveryCombinationAndOneReferencePerSceneAndSpp) {
  const Spec spec = parse(R"(
width = 8
height = 6
[grid]
scene = ["cornell", "tetra:1"]
format = ["fp32", "rpu24", "E7M16"]
isect = ["woop", "watertight"]
spp = [1, 2]
fidelity = ["functional", "cycle", "reference"]
)");
  // rpu24 and E7M16 are one format: 2 scenes x 2 formats x 2 tests x 2 spp x 2 levels.
  EXPECT_EQ(spec.points.size(), 32u);
  EXPECT_EQ(spec.references.size(), 4u);
  for (const Point& p : spec.points) {
    EXPECT_NE(p.fidelity, "reference");
    EXPECT_TRUE(p.format == "fp32" || p.format == "rpu24") << p.format;
    bool found = false;
    for (const Point& r : spec.references) {
      found = found || (r.id == p.reference && r.scene == p.scene && r.spp == p.spp);
    }
    EXPECT_TRUE(found) << p.id;
    EXPECT_EQ(p.width, 8);
  }
}

TEST(SweepSpec, IdsAreStableAndNameWhatChanges) {
  const std::string text = "[grid]\nscene = \"cornell\"\nformat = [\"fp32\", \"fp16\"]\n";
  const Spec a = parse(text), b = parse("# a comment\n" + text);
  ASSERT_EQ(a.points.size(), 2u);
  EXPECT_EQ(a.points[0].id, b.points[0].id);
  EXPECT_NE(a.points[0].id, a.points[1].id);
  EXPECT_TRUE(a.points[0].id.starts_with("functional-cornell-")) << a.points[0].id;
  // The checks are part of what a point measures: another leak count is another point.
  EXPECT_NE(parse("leak_rays = 7\n" + text).points[0].id, a.points[0].id);
}

TEST(SweepSpec, ATransformedSceneHasItsOwnReference) {
  const Spec spec = parse("[grid]\nscene = \"cornell\"\ntransform = [\"\", \"scale:-60\", \"translate:1e6\"]\n");
  ASSERT_EQ(spec.points.size(), 3u);
  ASSERT_EQ(spec.references.size(), 3u);
  EXPECT_EQ(spec.references[1].transform, "scale:-60");
  EXPECT_EQ(spec.points[1].reference, spec.references[1].id);
  const std::vector<std::string> args = spec.references[2].render_args();
  const auto at = std::find(args.begin(), args.end(), "--translate");
  ASSERT_NE(at, args.end());
  EXPECT_EQ(*(at + 1), "1000000");
  EXPECT_EQ(parse_transform("scale:60").scale_exponent, 60);
}

TEST(SweepSpec, SetAlternativesAndPoints) {
  const Spec spec = parse(R"(
[grid]
scene = "cornell"
config = "tiny"
set = ["", "node_cache.bytes=4096", ["shader_cores=2", "threads_per_core=8"]]
[[point]]
scene = "tetra:2"
fidelity = "cycle"
set = ["triangle_cache.bytes=4096"]
)");
  ASSERT_EQ(spec.points.size(), 4u);
  EXPECT_TRUE(spec.points[0].sets.empty());
  EXPECT_EQ(spec.points[2].sets, (std::vector<std::string>{"shader_cores=2", "threads_per_core=8"}));
  EXPECT_EQ(spec.points[3].fidelity, "cycle");
  EXPECT_EQ(spec.points[3].config, "default");
  const std::vector<std::string> args = spec.points[2].render_args();
  EXPECT_NE(std::find(args.begin(), args.end(), "threads_per_core=8"), args.end());
}

// Selected ray tracing is one axis: each selection its own point (in its canonical form,
// so that "4" and "4:0.05:material" are one), all of one scene sharing one reference.
TEST(SweepSpec, SelectIsAnAxis) {
  const Spec spec = parse(R"(
[grid]
scene = "cornell"
select = ["1", "4", "4:0.05:material", "3:0.1:primitive"]
fidelity = ["functional", "cycle"]
)");
  ASSERT_EQ(spec.points.size(), 6u);
  ASSERT_EQ(spec.references.size(), 1u);
  EXPECT_EQ(spec.points[0].select, "1");
  EXPECT_EQ(spec.points[2].select, "4:0.05:material");
  EXPECT_EQ(spec.points[4].select, "3:0.1:primitive");
  const std::vector<std::string> off = spec.points[0].render_args();
  EXPECT_EQ(std::find(off.begin(), off.end(), "--select"), off.end());
  const std::vector<std::string> args = spec.points[4].render_args();
  const auto at = std::find(args.begin(), args.end(), "--select");
  ASSERT_NE(at, args.end());
  EXPECT_EQ(*(at + 1), "3:0.1:primitive");
  // A point without selection keeps the id it had before the axis existed.
  EXPECT_EQ(spec.points[0].id, parse("[grid]\nscene = \"cornell\"\n").points[0].id);
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nselect = [\"1\", \"4:x\"]\n"),
            "test.toml:3:16: selection '4:x': threshold 'x' is not a finite number (the form is "
            "BLOCK[:THRESHOLD[:material|primitive]], for example 4:0.05:material; docs/selection.md)");
}

// A grid may render at its own size; its points and references are then their own.
TEST(SweepSpec, AGridMaySetItsImageSize) {
  const Spec spec = parse(R"(
width = 8
height = 6
[[grid]]
scene = "cornell"
[[grid]]
scene = "cornell"
width = 32
height = 24
)");
  ASSERT_EQ(spec.points.size(), 2u);
  ASSERT_EQ(spec.references.size(), 2u);
  EXPECT_EQ(spec.points[0].width, 8);
  EXPECT_EQ(spec.points[1].width, 32);
  EXPECT_EQ(spec.points[1].height, 24);
  EXPECT_EQ(spec.references[1].width, 32);
  EXPECT_EQ(spec.points[1].reference, spec.references[1].id);
}

TEST(SweepSpec, BadInputIsRefusedWithItsLine) {
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nformats = [\"fp32\"]\n"),
            "test.toml:3:11: unknown key 'formats' in [grid] (known: scene, transform, config, set, format, isect, "
            "firmware, select, spp, fidelity, width, height) (did you mean 'format'?)");
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\ntransform = [\"scale:101\"]\n"),
            "test.toml:3:14: transform 'scale:101' is neither scale:K (K a non-zero whole number in [-100, 100]) "
            "nor translate:D (D a non-zero number within 1e30)");
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nformat = [\"fp99\"]\n").substr(0, 47),
            "test.toml:3:11: unknown number format 'fp99': u");
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nfidelity = \"gate\"\n"),
            "test.toml:3:12: fidelity 'gate' is not one of reference, functional, cycle, rtl");
  const std::string missing = error_of("[grid]\nscene = \"no_such.json\"\n");
  EXPECT_EQ(missing.substr(0, 37), "test.toml:2:9: scene 'no_such.json': ");
  EXPECT_TRUE(missing.ends_with("/no_such.json: no such file")) << missing;
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nspp = [0]\n"), "test.toml:3:8: spp = 0 is outside [1, 65536]");
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nset = \"node_cache.bytes=1000\"\n").substr(0, 110),
            "test.toml:3:7: config 'default' with set node_cache.bytes=1000: configuration 'default': "
            "node_cache.bytes must");
  EXPECT_EQ(error_of("width = 0\n[grid]\nscene = \"cornell\"\n"), "test.toml:1:9: width = 0 is outside [1, 16384]");
  EXPECT_EQ(error_of("[grid]\nscene = \"cornell\"\nheight = 20000\n"),
            "test.toml:3:10: height = 20000 is outside [1, 16384]");
  EXPECT_EQ(error_of("name = \"x\"\n"), "test.toml: the sweep has no points: give a [grid] or [[point]] tables");
  EXPECT_EQ(error_of("[grid]\nfidelity = \"cycle\"\n"), "test.toml:1:1: [grid] names no scene");
  EXPECT_EQ(error_of("[grid\n").substr(0, 12), "test.toml:1:");
}

TEST(RayChecks, TheIcosphereIsOneClosedMeshAndAHoleOpensIt) {
  Scene sphere = test::icosphere(2);
  EXPECT_EQ(closed_meshes(sphere).size(), 1u);
  sphere.triangles.pop_back();
  EXPECT_EQ(closed_meshes(sphere).size(), 0u);
}

TEST(RayChecks, WatertightFp32NeverLeaksAndWoopDoesOnEdges) {
  const Scene sphere = test::icosphere(3);
  KdBuildConfig build;
  const RayChecks watertight = check_rays(sphere, build, IsectMode::kWatertight, 16, 16, false, 20000, 1);
  EXPECT_EQ(watertight.closed_meshes, 1u);
  EXPECT_EQ(watertight.leak_rays, 20000u);
  EXPECT_EQ(watertight.leaks, 0u);
  EXPECT_EQ(watertight.primary_rays, 0u);
  const RayChecks woop = check_rays(sphere, build, IsectMode::kWoop, 16, 16, false, 20000, 1);
  EXPECT_GT(woop.leaks, 0u);
}

TEST(RayChecks, PrimaryRaysAgreeWithFp64InFp32AndLessInANarrowFormat) {
  const Scene scene = make_builtin_scene("balls:1");
  KdBuildConfig build;
  const RayChecks fp32 = check_rays(scene, build, IsectMode::kWatertight, 48, 32, true, 0, 1);
  EXPECT_EQ(fp32.primary_rays, 48u * 32u);
  EXPECT_LE(fp32.hit_mismatches, 2u);  // ties on shared edges only
  build.format = fp::format_by_name("fp16");
  const RayChecks fp16 = check_rays(scene, build, IsectMode::kWatertight, 48, 32, true, 0, 1);
  EXPECT_GT(fp16.hit_mismatches, fp32.hit_mismatches);
  EXPECT_EQ(fp16.leak_rays, 0u);
}

TEST(RayChecks, ExtremeRaysAgreeWithFp64InFp32AndNotInFp16) {
  const Scene scene = make_builtin_scene("cornell");
  KdBuildConfig build;
  const RayChecks fp32 = check_rays(scene, build, IsectMode::kWatertight, 8, 8, false, 0, 3, 2000);
  EXPECT_EQ(fp32.axis_rays, 2000u);
  EXPECT_EQ(fp32.surface_rays, 2000u);
  // Watertight fp32 against fp64 on the same rays: ties at shared edges at most.
  EXPECT_LE(fp32.axis_mismatches, 20u);
  EXPECT_LE(fp32.grazing_mismatches, 20u);
  EXPECT_LE(fp32.surface_mismatches, 20u);
  build.format = fp::format_by_name("fp16");
  const RayChecks fp16 = check_rays(scene, build, IsectMode::kWatertight, 8, 8, false, 0, 3, 2000);
  EXPECT_GT(fp16.grazing_mismatches + fp16.surface_mismatches, 20u);
}

TEST(Area, TheDatapathSumsTheSynthesisedUnits) {
  // fma + misc + divsqrt + iu_woop + tu_woop in fp32 (docs/area.md).
  EXPECT_EQ(datapath_cells(fp::kFp32, IsectMode::kWoop), 10120u + 3068u + 2179u + 29140u + 58579u);
  EXPECT_FALSE(datapath_cells(fp::format_by_name("bf16"), IsectMode::kWoop).has_value());
  EXPECT_TRUE(chip_cells("default", IsectMode::kWoop).has_value());
  EXPECT_FALSE(chip_cells("rpu2005", IsectMode::kWatertight).has_value());
}

}  // namespace
}  // namespace rpu::sweep
