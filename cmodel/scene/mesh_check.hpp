#pragma once

#include <filesystem>
#include <string>

namespace rpu {

// The readers checked before Assimp reads a file; every other format is left to Assimp.
enum class MeshFormat { kPly, kOff, kStl, kObj, kOther };

// Checks, before Assimp allocates anything, that `bytes` (the whole file at `path`) can
// hold what its header declares, so that memory stays proportional to the file's size
// and Assimp never reads past the end (docs/scene-format.md, "Bad mesh files"):
//   PLY  every element count times the least bytes an instance takes, then every list
//        length in the data against what is left of its line (ascii) or of the file;
//   OFF  the vertex and face counts times the least bytes of their lines;
//   STL  a binary file's triangle count against 84 + 50 x count == its size; an ascii
//        file walked as Assimp walks it, refused where Assimp would throw (and leak);
//   OBJ  line statements of one vertex, on which Assimp throws (and leaks).
// The PLY header is read as Assimp 5.2 reads it, quirks included, since the counts it
// acts on are the ones that must be bounded. Throws rpu::Error naming the file, the
// element and the offset or line.
void check_mesh_bytes(const std::filesystem::path& path, MeshFormat format, const std::string& bytes);

}  // namespace rpu
