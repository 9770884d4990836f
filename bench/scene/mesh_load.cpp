// Loads one mesh file with rpu::load_mesh and does nothing else, so that its peak RSS
// under `/usr/bin/time -v` is what loading the file costs (docs/scene-format.md, "Bad
// mesh files"; scripts/bench-record mesh-memory runs it). Without a file it exits at
// once: the empty run, whose RSS (the binary and its libraries) is subtracted.
//
//   build/release/bench/scene/mesh_load [FILE]
//
// Prints one JSON line: {"triangles": N, "warnings": [...]} when the file loads,
// {"error": "..."} when load_mesh refuses it (both exit 0: refusing is an outcome).
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "scene/mesh.hpp"

int main(int argc, char** argv) {
  if (argc > 2) {
    std::fprintf(stderr, "usage: mesh_load [FILE]\n");
    return 2;
  }
  if (argc == 1) return 0;
  nlohmann::json out;
  try {
    const rpu::Scene mesh = rpu::load_mesh(argv[1], rpu::MeshOptions{});
    out["triangles"] = mesh.triangles.size();
    out["warnings"] = mesh.warnings;
  } catch (const rpu::Error& e) {
    out["error"] = e.what();
  }
  std::printf("%s\n", out.dump().c_str());
  return 0;
}
