#pragma once

#include "fp/format.hpp"
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

// The scene as a frame renders it: every length times 2^-s, s = kd_scale_exponent(scene,
// format), so that the shaders' arithmetic sees, like the kd-tree, the same numbers
// inside the format's range for the scene at any power-of-two scale: the image of a
// scene scaled by 2^k is the same bit for bit (docs/traversal.md "Limits of the formats"). The kd scale of
// its memory image is then 0.
Scene chip_space_scene(const Scene& scene, fp::Format format);

SceneImage make_scene_image(const Scene& scene, const KdBuildConfig& build, IsectMode mode);

}  // namespace rpu::functional
