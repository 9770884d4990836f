// libFuzzer target: parse_scene_json on arbitrary text, mesh paths relative to scenes/
// (so meshes/floor.obj loads) and an empty mesh cache (so @meshes/ fails fast). A scene
// it accepts must also become a valid memory image (over a one-leaf tree) or be refused
// with rpu::Error. Only rpu::Error may escape either step.
//
// Inputs that ask a built-in generator for a large scene are skipped (large_scene.hpp).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string_view>

#include "common/error.hpp"
#include "memory/memory_image.hpp"
#include "scene/geometry.hpp"
#include "scene/scene_file.hpp"
#include "large_scene.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("RPU_MESH_DIR", "/nonexistent/rpu-fuzz-mesh-cache", 1);
  return 0;
}

// Scenes that run in well under a second here: balls 3 (184 k triangles), tetra 7 (16 k),
// cornell 128 (16 k).
constexpr rpu::fuzz::GeneratorLimits kLimits{3, 7, 128, 7, 20000};

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (rpu::fuzz::asks_for_large_scene(text, kLimits)) return 0;
  try {
    const rpu::Scene scene = rpu::parse_scene_json(text, RPU_SOURCE_DIR "/scenes", "fuzz.json");
    rpu::KdTree tree;
    const auto triangles = static_cast<std::uint32_t>(scene.triangles.size());
    tree.nodes = {rpu::KdNode::leaf(triangles, 0)};
    tree.prim_refs.resize(triangles);
    std::iota(tree.prim_refs.begin(), tree.prim_refs.end(), 0u);
    const rpu::Bounds box = rpu::scene_bounds(scene);
    tree.bounds_lo = glm::vec3(box.lo);
    tree.bounds_hi = glm::vec3(box.hi);
    rpu::build_memory_image(scene, tree, rpu::IsectMode::kWoop);
  } catch (const rpu::Error&) {
    // The one way to reject a scene.
  }
  return 0;
}
