#pragma once

#include <string_view>

#include "scene/scene.hpp"

namespace rpu {

// What the CLI's scene argument means:
//   ""                   the default scene, the Cornell box;
//   "*.json"             a JSON scene file (docs/scene-format.md);
//   "cornell", "balls:4" a built-in generator, optionally with a size;
//   "@meshes/NAME"       a mesh in the mesh cache, as a bare mesh;
//   any other file       a bare mesh read by Assimp, framed by a default camera.
// Throws rpu::Error when the argument is none of these.
Scene resolve_scene(std::string_view arg);

}  // namespace rpu
