#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

// A sweep (docs/sweeps.md): a TOML file naming a grid, or a list, of render runs over
// scenes, configurations and --set changes, number formats, intersection tests, firmware,
// selected ray tracing, samples per pixel and fidelity levels. Parsing expands it into points; each point is one
// independent `rpu render` run measured against the reference render of its scene.
namespace rpu::sweep {

inline constexpr std::string_view kFidelities[] = {"reference", "functional", "cycle", "rtl"};

struct Point {
  std::string id;        // stable across runs: "<fidelity>-<scene>-<hash of canonical()>"
  std::string scene;     // a built-in name, or an absolute path
  std::string fidelity;  // one of kFidelities: the rpu render backend
  std::string config;    // a named configuration, or an absolute path to a TOML file
  std::vector<std::string> sets;  // "key=value", applied in order
  std::string format;    // empty: the configuration's format
  std::string isect = "woop";
  std::string transform;  // "", "scale:K" (the scene times 2^K) or "translate:D" (moved by D, D, D)
  std::vector<std::string> firmware;  // absolute paths; empty: the built-in whitted.s
  std::string select = "1";  // selected ray tracing (docs/selection.md), as render/selection.hpp writes it
  int width = 64, height = 64, spp = 1, max_depth = 5;
  std::uint64_t seed = 1;
  std::string reference;  // id of the reference point it is measured against; "" for a reference

  // Every field that decides what the point measures, one per line: the id hashes it.
  std::string canonical() const;
  // The `rpu render` arguments after "render", without outputs, --stats or --compare.
  std::vector<std::string> render_args() const;
};

struct Spec {
  std::string name;
  std::uint32_t leak_rays = 4096;  // rays from inside each scene's closed meshes; 0: none
  bool hit_check = true;           // primary rays against an fp64 trace
  std::uint32_t extreme_rays = 1024;  // axis-parallel, grazing and on-surface rays, each; 0: none
  std::vector<Point> references;   // one per scene and image: rendered first
  std::vector<Point> points;       // the rest, each naming its reference
};

// Parses a sweep file's text; relative paths (scenes, configurations, firmware) are
// resolved against `base_dir` and must exist. Throws rpu::Error naming `source`, the line
// and the key for malformed TOML, an unknown key (with the nearest known one), a value of
// the wrong type or out of range, an unknown format, configuration or --set, and a sweep
// of no points.
// The point's transform: the scale exponent K and the offset D of "scale:K" /
// "translate:D" (0 and 0 for none).
struct Transform {
  int scale_exponent = 0;
  double offset = 0.0;
};
Transform parse_transform(std::string_view text);

Spec parse_spec(std::string_view text, const std::string& source, const std::filesystem::path& base_dir);
Spec read_spec(const std::filesystem::path& file);

}  // namespace rpu::sweep
