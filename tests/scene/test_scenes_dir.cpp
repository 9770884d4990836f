// Every scene file in scenes/ loads. Those naming "@meshes/..." need scripts/fetch-meshes
// to have run: without the cache they fail with the loader's message, never skip.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.hpp"
#include "scene/geometry.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

Scene load(const std::string& name) {
  const fs::path path = fs::path(RPU_SOURCE_DIR) / "scenes" / name;
  try {
    return resolve_scene(path.string());
  } catch (const Error& e) {
    ADD_FAILURE() << e.what();
  }
  return {};
}

void expect_valid(const Scene& s) {
  ASSERT_FALSE(s.triangles.empty());
  ASSERT_EQ(s.material_ids.size(), s.triangles.size());
  for (const std::uint32_t m : s.material_ids) ASSERT_LT(m, s.materials.size());
  EXPECT_FALSE(s.lights.empty());
}

TEST(ScenesDir, EveryJsonFileLoads) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(fs::path(RPU_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() == ".json") names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"balls.json", "bunny.json", "cornell.json", "cornell_distributed.json",
                                             "dragon.json", "dragon_203k.json", "spider.json", "tetra.json"}));
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    expect_valid(load(name));
  }
}

// The distributed effects' scene: the Cornell box with a lens and a glossy block.
TEST(ScenesDir, TheDistributedCornellBoxHasALensAndAGlossyBlock) {
  const Scene s = load("cornell_distributed.json");
  EXPECT_EQ(s.triangles.size(), resolve_scene("cornell").triangles.size());
  EXPECT_EQ(s.camera.aperture_radius, 15.0);
  EXPECT_EQ(s.camera.focus_distance, 1080.0);
  const auto glossy = std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) {
    return m.shader == "glossy";
  });
  ASSERT_NE(glossy, s.materials.end());
  EXPECT_EQ(glossy->roughness, 0.15);
}

TEST(ScenesDir, BuiltinTwinsMatchTheBuiltins) {
  EXPECT_EQ(load("cornell.json").triangles.size(), resolve_scene("cornell").triangles.size());
  EXPECT_EQ(load("balls.json").triangles.size(), resolve_scene("balls:3").triangles.size());
  EXPECT_EQ(load("tetra.json").triangles.size(), 4096u);
}

TEST(ScenesDir, RealMeshesHaveTheirPublishedTriangleCounts) {
  // Each mesh scene adds one floor.obj quad (two triangles) per floor or mirror.
  EXPECT_EQ(load("bunny.json").triangles.size(), 3674u + 4u);
  EXPECT_EQ(load("dragon.json").triangles.size(), 47794u + 2u);
  EXPECT_EQ(load("dragon_203k.json").triangles.size(), 202520u + 2u);
  // The spider OBJ has 56 zero-area faces; they are dropped with one warning.
  const Scene spider = load("spider.json");
  EXPECT_EQ(spider.triangles.size(), 1312u + 2u);
  ASSERT_EQ(spider.warnings.size(), 1u);
  EXPECT_NE(spider.warnings[0].find("spider.obj: dropped 56 degenerate triangles (56 zero area)"),
            std::string::npos);
}

}  // namespace
}  // namespace rpu
