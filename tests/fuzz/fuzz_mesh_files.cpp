// libFuzzer target: load_mesh on arbitrary bytes written to a file. It may reject a file
// only with rpu::Error; any other exception, crash, leak, UB or out-of-memory is a
// finding, and so is an Assimp ai_assert (which rpu turns into an rpu::Error): the
// checks before Assimp and before post-processing are meant to leave none to fire.
//
// The reader follows from the first byte, so that every seed is a plain mesh file:
// "ply" -> .ply (ascii and binary); "OFF" or one of its prefixes (S, C, N, 4, n) or a
// digit -> .off; "solid" -> .stl (ascii); "v", "f", "#", "o", "g" -> .obj; any other
// byte b -> .obj, .ply, .off or .stl by b % 4 (a binary STL seed starts with 'c').
// The low bit of the second byte asks for smooth normals (GenSmoothNormals).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "common/error.hpp"
#include "scene/mesh.hpp"

namespace {

std::filesystem::path g_dir;

const char* extension_for(std::uint8_t first) {
  switch (first) {
    case 'p': case 'P': return ".ply";
    case 'O': case 'S': case 'C': case 'N': case '4': case 'n': return ".off";
    case 's': return ".stl";
    case 'v': case 'f': case '#': case 'o': case 'g': return ".obj";
    default: break;
  }
  if (first >= '0' && first <= '9') return ".off";
  static constexpr const char* kByRemainder[] = {".obj", ".ply", ".off", ".stl"};
  return kByRemainder[first % 4];
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_dir = std::filesystem::temp_directory_path() / ("rpu_fuzz_mesh_" + std::to_string(getpid()));
  std::filesystem::create_directories(g_dir);
  std::atexit([] { std::filesystem::remove_all(g_dir); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::filesystem::path path = g_dir / (std::string("input") + extension_for(data[0]));
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  rpu::MeshOptions options;
  options.smooth = size > 1 && (data[1] & 1) != 0;
  try {
    rpu::load_mesh(path, options);
  } catch (const rpu::Error& e) {
    // The handler's message follows "cannot read the mesh: " where Assimp's own error
    // text would; anywhere else the words may be quoted from the input.
    if (std::string_view(e.what()).starts_with(path.string() + ": cannot read the mesh: Assimp's internal check")) {
      std::abort();
    }
  }
  std::filesystem::remove(path);
  return 0;
}
