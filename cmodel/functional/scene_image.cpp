#include "functional/scene_image.hpp"

namespace rpu::functional {

SceneImage make_scene_image(const Scene& scene, const KdBuildConfig& build, IsectMode mode) {
  const KdTree tree = build_kdtree(scene, build);
  SceneImage out;
  out.image = build_memory_image(scene, tree, mode);
  out.layout = validate_memory_image(out.image.bytes, scene.source);
  out.tree_stats = tree.stats;
  return out;
}

}  // namespace rpu::functional
