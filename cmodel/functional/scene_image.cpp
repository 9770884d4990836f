#include "functional/scene_image.hpp"

#include "scene/geometry.hpp"

namespace rpu::functional {

Scene chip_space_scene(const Scene& scene, fp::Format format) {
  Scene out = scene;
  scale_scene(out, -kd_scale_exponent(scene, format));
  return out;
}

SceneImage make_scene_image(const Scene& scene, const KdBuildConfig& build, IsectMode mode) {
  const KdTree tree = build_kdtree(scene, build);
  SceneImage out;
  out.image = build_memory_image(scene, tree, mode);
  out.layout = validate_memory_image(out.image.bytes, scene.source);
  out.tree_stats = tree.stats;
  return out;
}

}  // namespace rpu::functional
