// libFuzzer target: scene file text -> parse_scene_json -> build_kdtree -> memory image
// in both intersection modes -> validate_memory_image. Mesh paths resolve against
// corpus/mesh_files (the mesh fuzzer's seeds, small files of every format) and the mesh
// cache is empty. Parsing, the build and the layout may refuse a scene only with
// rpu::Error; an image they produce must then validate and describe the scene, or it is
// a finding, as is any other exception, crash, leak or UB.
//
// Generator sizes are capped (large_scene.hpp) so that an iteration, kd build included,
// stays in milliseconds under ASan.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "common/error.hpp"
#include "kdtree/kdtree.hpp"
#include "memory/memory_image.hpp"
#include "scene/scene_file.hpp"
#include "large_scene.hpp"

namespace {

// balls 1 (2 k triangles), tetra 5 (1 k), cornell 32 (990).
constexpr rpu::fuzz::GeneratorLimits kLimits{1, 5, 32, 5, 1000};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("RPU_MESH_DIR", "/nonexistent/rpu-fuzz-mesh-cache", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (rpu::fuzz::asks_for_large_scene(text, kLimits)) return 0;
  std::optional<rpu::Scene> scene;
  std::optional<rpu::KdTree> tree;
  try {
    scene = rpu::parse_scene_json(text, RPU_SOURCE_DIR "/tests/fuzz/corpus/mesh_files", "fuzz.json");
    tree = rpu::build_kdtree(*scene, rpu::KdBuildConfig{});
  } catch (const rpu::Error&) {
    return 0;  // the one way to refuse a scene
  }
  for (const rpu::IsectMode mode : {rpu::IsectMode::kWoop, rpu::IsectMode::kWatertight}) {
    std::optional<rpu::MemoryImage> image;
    try {
      image = rpu::build_memory_image(*scene, *tree, mode);
    } catch (const rpu::Error&) {
      continue;  // a degenerate triangle has no Woop transform
    }
    const rpu::ImageLayout layout = rpu::validate_memory_image(image->bytes, "fuzz.rpu");
    if (layout.triangle_count != scene->triangles.size() || layout.vertex_count != scene->positions.size() ||
        layout.isect_mode != mode) {
      std::abort();
    }
  }
  return 0;
}
