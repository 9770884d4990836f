#pragma once

#include "kdtree/kdtree.hpp"
#include "memory/memory_image.hpp"
#include "scene/scene.hpp"

namespace rpu::functional {

// A scene turned into what the chip reads: kd-tree built, memory image laid out and
// validated. The layout refers into image.bytes, so keep them together.
struct SceneImage {
  MemoryImage image;
  ImageLayout layout;
  KdTreeStats tree_stats;
};

SceneImage make_scene_image(const Scene& scene, const KdBuildConfig& build, IsectMode mode);

}  // namespace rpu::functional
