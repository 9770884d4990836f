#pragma once

#include <cstdint>
#include <filesystem>
#include <string_view>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace rpu {

// Scene files name cached meshes as "@meshes/NAME" (scripts/fetch-meshes fills the cache).
inline constexpr std::string_view kMeshCachePrefix = "@meshes/";

// ${RPU_MESH_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/rpu/meshes}, as in scripts/fetch-meshes.
std::filesystem::path mesh_cache_dir();

// Resolves a mesh reference: "@meshes/NAME" in the mesh cache, otherwise a path
// relative to `base_dir` (the directory of the scene file). Throws rpu::Error when the
// file does not exist; for a cached mesh the message says to run scripts/fetch-meshes.
std::filesystem::path resolve_mesh_path(std::string_view reference,
                                        const std::filesystem::path& base_dir);

struct MeshOptions {
  glm::dmat4 transform{1.0};   // object to world; must be invertible
  bool smooth = false;         // generate smooth normals when the file has none
  std::uint32_t material_id = 0;  // given to every triangle
};

// Reads a mesh file with Assimp into world-space geometry: the node graph's transforms
// are applied, then options.transform. Returns a Scene holding only geometry (and its
// warnings): normals when the file has them or options.smooth asks for them, uvs when
// the file has them. Degenerate triangles are dropped with one warning; a file without
// triangles (points or lines only) gives no geometry and the warning "no triangles in the
// file". Throws rpu::Error naming the file for a file Assimp cannot read (with Assimp's
// message), for one that check_mesh_bytes refuses (mesh_check.hpp: counts beyond the
// file's size, data ending early), for a face without vertices or naming a vertex past
// the last, for a vertex that is not finite, and for an Assimp internal check that fails.
Scene load_mesh(const std::filesystem::path& path, const MeshOptions& options);

}  // namespace rpu
