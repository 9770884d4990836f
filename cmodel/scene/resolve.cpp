#include "scene/resolve.hpp"

#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "scene/mesh.hpp"
#include "scene/procedural.hpp"
#include "scene/scene_file.hpp"

namespace rpu {

Scene resolve_scene(std::string_view arg) {
  namespace fs = std::filesystem;
  if (arg.empty()) return make_cornell_box();
  if (arg.ends_with(".json")) return load_scene_file(fs::path(arg));
  if (arg.starts_with(kMeshCachePrefix)) return load_bare_mesh(resolve_mesh_path(arg, {}));
  if (is_builtin_scene(arg)) return make_builtin_scene(arg);
  const fs::path path(arg);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(path, ec))) {
    check_input_file(path, "the scene");
    return load_bare_mesh(path);
  }
  throw Error(fmt::format(
      "{}: no such scene: not a file, nor a built-in scene ({}; a size may follow, as in "
      "balls:4)",
      arg, fmt::join(builtin_scene_names(), ", ")));
}

}  // namespace rpu
