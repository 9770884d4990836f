#include "scene/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <assimp/BaseImporter.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "scene/geometry.hpp"
#include "scene/mesh_check.hpp"

// Debian builds libassimp with its ai_assert checks on, and their handler aborts the
// process. Assimp 5.2 keeps setAiAssertHandler out of the library's exports, so the
// handler is replaced by defining the function every ai_assert calls: the dynamic linker
// binds the library's calls to the executable's definition. Thrown inside a reader, the
// error becomes Assimp's read error; the checks below are meant to leave none to throw.
namespace Assimp {
void aiAssertViolation(const char* expression, const char* file, int line);
void aiAssertViolation(const char* expression, const char* file, int line) {
  throw rpu::Error(fmt::format("Assimp's internal check \"{}\" failed ({}:{})", expression, file, line));
}
}  // namespace Assimp

namespace rpu {
namespace {

namespace fs = std::filesystem;

glm::dmat4 to_glm(const aiMatrix4x4& a) {
  glm::dmat4 m;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) m[col][row] = a[row][col];
  }
  return m;
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string vertex_name(const aiScene& ai, unsigned mesh, unsigned vertex) {
  return ai.mNumMeshes == 1 ? fmt::format("vertex {}", vertex)
                            : fmt::format("vertex {} of mesh {}", vertex, mesh);
}

std::string face_name(const aiScene& ai, unsigned mesh, unsigned face) {
  return ai.mNumMeshes == 1 ? fmt::format("face {}", face)
                            : fmt::format("face {} of mesh {}", face, mesh);
}

// The reader Importer::ReadFile (Importer.cpp, 5.2) hands the file to: the one reader
// that claims its extension, else the first claimant, else the first reader at all, whose
// signature check takes it.
MeshFormat reader_format(const Assimp::Importer& importer, const fs::path& path) {
  const std::string file = path.string();
  const auto claims = [&](Assimp::BaseImporter& reader) {
    std::set<std::string> extensions;
    reader.GetExtensionList(extensions);
    for (const std::string& e : extensions) {
      const std::string suffix = "." + e;
      if (suffix.size() <= file.size() &&
          std::equal(suffix.begin(), suffix.end(), file.end() - static_cast<std::ptrdiff_t>(suffix.size()),
                     [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) ==
                                                 std::tolower(static_cast<unsigned char>(b)); })) {
        return true;
      }
    }
    return false;
  };
  std::vector<Assimp::BaseImporter*> claimants, all;
  for (std::size_t i = 0; i < importer.GetImporterCount(); ++i) {
    Assimp::BaseImporter* reader = importer.GetImporter(i);
    all.push_back(reader);
    if (claims(*reader)) claimants.push_back(reader);
  }
  Assimp::BaseImporter* chosen = claimants.size() == 1 ? claimants[0] : nullptr;
  for (const auto* candidates : {&claimants, &all}) {
    for (Assimp::BaseImporter* reader : *candidates) {
      if (chosen == nullptr && reader->CanRead(file, importer.GetIOHandler(), true)) chosen = reader;
    }
  }
  if (chosen == nullptr) return MeshFormat::kOther;
  std::set<std::string> extensions;
  chosen->GetExtensionList(extensions);
  if (extensions.contains("ply")) return MeshFormat::kPly;
  if (extensions.contains("off")) return MeshFormat::kOff;
  if (extensions.contains("stl")) return MeshFormat::kStl;
  if (extensions.contains("obj")) return MeshFormat::kObj;
  return MeshFormat::kOther;
}

// Readers leave faces without indices (an OFF file with fewer face lines than it
// declares) and indices past the last vertex (corrupt files); post-processing asserts or
// crashes on either, so they are errors here, before it runs.
void check_faces(const aiScene& ai, const fs::path& path) {
  for (unsigned m = 0; m < ai.mNumMeshes; ++m) {
    const aiMesh& mesh = *ai.mMeshes[m];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices == 0 || face.mIndices == nullptr) {
        throw Error(fmt::format("{}: {} has no vertices (the file holds fewer faces than it "
                                "declares, or a face line is empty)",
                                path.string(), face_name(ai, m, f)));
      }
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= mesh.mNumVertices) {
          throw Error(fmt::format("{}: {} names vertex {}, but there are {} vertices",
                                  path.string(), face_name(ai, m, f), face.mIndices[k],
                                  mesh.mNumVertices));
        }
      }
    }
  }
}

bool has_surfaces(const aiScene& ai) {
  for (unsigned m = 0; m < ai.mNumMeshes; ++m) {
    const aiMesh& mesh = *ai.mMeshes[m];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      if (mesh.mFaces[f].mNumIndices >= 3) return true;
    }
  }
  return false;
}

// Assimp's file readers accept "nan" and overflowing literals; a non-finite vertex would
// poison the kd-tree bounds, so it is an error naming the vertex in file order.
void check_finite(const aiScene& ai, const fs::path& path) {
  for (unsigned m = 0; m < ai.mNumMeshes; ++m) {
    const aiMesh& mesh = *ai.mMeshes[m];
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      if (!finite({p.x, p.y, p.z})) {
        throw Error(fmt::format("{}: {} is not finite ({}, {}, {})", path.string(),
                                vertex_name(ai, m, v), p.x, p.y, p.z));
      }
    }
  }
}

// One Assimp mesh placed by `to_world` as a geometry-only Scene.
Scene convert_mesh(const aiScene& ai, unsigned index, const glm::dmat4& to_world,
                   const MeshOptions& options, const fs::path& path) {
  const aiMesh& mesh = *ai.mMeshes[index];
  const glm::dmat3 linear(to_world);
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  // A mirroring transform turns the winding inside out; swapping two corners keeps
  // the geometric normal on the same side as the shading normals.
  const bool flip = glm::determinant(linear) < 0.0;
  Scene part;
  part.positions.reserve(mesh.mNumVertices);
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    const glm::dvec3 w = glm::dvec3(to_world * glm::dvec4(p.x, p.y, p.z, 1.0));
    const glm::vec3 stored(w);
    if (!finite(glm::dvec3(stored))) {
      throw Error(fmt::format("{}: {} is not finite after the transform ({}, {}, {})",
                              path.string(), vertex_name(ai, index, v), stored.x, stored.y,
                              stored.z));
    }
    part.positions.push_back(stored);
  }
  if (mesh.HasNormals()) {
    part.normals.reserve(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& n = mesh.mNormals[v];
      const glm::dvec3 w = normal_matrix * glm::dvec3(n.x, n.y, n.z);
      const double len = glm::length(w);
      // Assimp leaves NaN normals on vertices of degenerate faces; those faces are
      // dropped below, so any unit vector will do for them.
      part.normals.emplace_back(len > 0.0 && std::isfinite(len) ? w / len
                                                                 : glm::dvec3(0.0, 0.0, 1.0));
    }
  }
  if (mesh.HasTextureCoords(0)) {
    part.uvs.reserve(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      part.uvs.emplace_back(mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y);
    }
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines are not surfaces
    glm::uvec3 t(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
    if (flip) std::swap(t.y, t.z);
    part.triangles.push_back(t);
    part.material_ids.push_back(options.material_id);
  }
  weld_identical_vertices(part);
  if (options.smooth && part.normals.empty()) generate_smooth_normals(part);
  return part;
}

void add_node(const aiScene& ai, const aiNode& node, const glm::dmat4& parent,
              const MeshOptions& options, const fs::path& path, Scene& out) {
  const glm::dmat4 to_world = parent * to_glm(node.mTransformation);
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    if (node.mMeshes[k] >= ai.mNumMeshes) {
      throw Error(fmt::format("{}: node \"{}\" names mesh {}, but there are {} meshes", path.string(),
                              node.mName.C_Str(), node.mMeshes[k], ai.mNumMeshes));
    }
    append_geometry(out, convert_mesh(ai, node.mMeshes[k], to_world, options, path));
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    add_node(ai, *node.mChildren[c], to_world, options, path, out);
  }
}

}  // namespace

fs::path mesh_cache_dir() {
  if (const char* dir = std::getenv("RPU_MESH_DIR"); dir != nullptr && *dir != '\0') {
    return dir;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return fs::path(xdg) / "rpu" / "meshes";
  }
  const char* home = std::getenv("HOME");
  return fs::path(home != nullptr ? home : "") / ".cache" / "rpu" / "meshes";
}

fs::path resolve_mesh_path(std::string_view reference, const fs::path& base_dir) {
  if (reference.starts_with(kMeshCachePrefix)) {
    const fs::path dir = mesh_cache_dir();
    const fs::path path = dir / reference.substr(kMeshCachePrefix.size());
    if (!fs::exists(path)) {
      throw Error(fmt::format(
          "{} is not in the mesh cache {} (run scripts/fetch-meshes to fetch the meshes; "
          "RPU_MESH_DIR chooses another cache)",
          reference, dir.string()));
    }
    return path;
  }
  const fs::path path = base_dir / fs::path(reference);
  if (!fs::exists(path)) {
    throw Error(fmt::format("mesh file {} not found", path.string()));
  }
  return path;
}

Scene load_mesh(const fs::path& path, const MeshOptions& options) {
  const std::string bytes = read_input_file(path, "the mesh file");
  const glm::dmat3 linear(options.transform);
  if (!std::isfinite(glm::determinant(linear)) || glm::determinant(linear) == 0.0) {
    throw Error(fmt::format("{}: the transform is singular (a zero scale?)", path.string()));
  }
  Assimp::Importer importer;
  // Points and lines cannot be hit by a ray: let SortByPType remove them.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  check_mesh_bytes(path, reader_format(importer, path), bytes);
  // Read without post-processing first, so that vertex numbers in errors follow the file.
  const aiScene* ai = importer.ReadFile(path.string(), 0);
  if (ai == nullptr) {
    throw Error(fmt::format("{}: cannot read the mesh: {}", path.string(),
                            importer.GetErrorString()));
  }
  check_faces(*ai, path);
  check_finite(*ai, path);
  Scene out;
  // Post-processing fails when SortByPType removes every mesh.
  if (!has_surfaces(*ai)) {
    out.warnings.push_back(fmt::format("{}: no triangles in the file", path.string()));
    return out;
  }
  // Welding and smooth normals are ours (convert_mesh): Assimp's use distance
  // tolerances, so the same mesh at another scale would weld and shade differently.
  ai = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_SortByPType);
  if (ai == nullptr || ai->mRootNode == nullptr) {
    throw Error(fmt::format("{}: cannot read the mesh: {}", path.string(),
                            importer.GetErrorString()));
  }
  add_node(*ai, *ai->mRootNode, options.transform, options, path, out);
  if (out.triangles.empty()) {
    out.warnings.push_back(fmt::format("{}: no triangles in the file", path.string()));
    return out;
  }
  drop_degenerate_triangles(out, path.string());
  return out;
}

}  // namespace rpu
