#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "scene/geometry.hpp"
#include "scene/scene.hpp"

namespace rpu {

// A scene file names its meshes and holds no geometry: one larger than this is refused
// before it is read, which bounds the memory its parse takes (docs/robustness.md).
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{4} << 20;

// Reads a JSON scene file (docs/scene-format.md). Throws rpu::Error naming the file and
// the line:column (malformed JSON) or the JSON pointer of the offending value.
Scene load_scene_file(const std::filesystem::path& path);

// The same from JSON text in memory: mesh paths resolve against `base_dir`, messages
// name `source`. load_scene_file is this on the file's text and directory.
Scene parse_scene_json(std::string_view text, const std::filesystem::path& base_dir, const std::string& source);

// A bare mesh file as a scene: the default grey material, a camera framing it and a
// point light near the camera (docs/scene-format.md, "Bare meshes").
Scene load_bare_mesh(const std::filesystem::path& path);

// A camera looking at the centre of `box` from a diagonal above and to the front
// (+x, +y, +z: y is up), vfov 40 degrees, far enough that the whole box is in view.
Camera frame_bounds(const Bounds& box);

// A white point light a little above and beside `camera`.
Light light_near(const Camera& camera, const Bounds& box);

// The grey material bare meshes and meshes without a material get, named "default",
// with an ambient term so that unlit sides are not black.
Material default_material();

}  // namespace rpu
