#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "kdtree/kdtree.hpp"
#include "rpu/spec.hpp"
#include "scene/scene.hpp"

namespace rpu {

// How the intersection unit tests triangles, and so what an intersection record holds.
enum class IsectMode : std::uint32_t {
  kWoop = 0,        // Woop's unit-triangle transform: 3 float4 rows (RPU 2005)
  kWatertight = 1,  // Woop, Benthin, Wald 2013: the three vertices as float4
};

// The size of an intersection record in this mode (spec/memory_map.toml [triangle_record]).
inline std::uint32_t isect_record_bytes(IsectMode mode) {
  return mode == IsectMode::kWoop ? spec::memory::kTriangleRecordWoopBytes
                                  : spec::memory::kTriangleRecordWatertightBytes;
}

// Everything the chip reads, as one little-endian byte image (docs/memory-map.md).
struct MemoryImage {
  std::vector<std::uint8_t> bytes;
};

// Where each section of a validated image lies. Offsets are byte addresses in the
// image; count is the number of records.
struct ImageSection {
  std::uint32_t offset = 0;
  std::uint32_t bytes = 0;
  std::uint32_t count = 0;
};

struct ImageLayout {
  ImageSection scene, kd_nodes, prim_refs, isect_records, vertex_normals, vertex_uvs, triangles, materials,
      lights, camera, vertex_positions;
  glm::vec3 bounds_lo{0.0f}, bounds_hi{0.0f};  // the kd-tree's root box, in kd space
  int kd_scale_exponent = 0;                    // s: kd space = world space x 2^-s
  IsectMode isect_mode = IsectMode::kWoop;
  std::uint32_t triangle_count = 0;
  float ray_epsilon = 0.0f;
  std::uint32_t ray_offset_shift = 0;  // 23 - the format's fraction bits (spec/memory_map.toml [ray_offset])
  // The rest of the scene record, so that a reader needs nothing but the layout.
  std::uint32_t vertex_count = 0;  // = vertex_positions; vertex_normals / vertex_uvs hold 0 or this many
  std::uint32_t material_count = 0;
  std::uint32_t light_count = 0;
  glm::vec3 background{0.0f};
  std::uint32_t total_bytes = 0;
};

// Lays the scene and its kd-tree out as one image (docs/memory-map.md) and validates
// the result. Throws rpu::Error naming scene.source for a triangle whose Woop
// transform is not finite (a degenerate triangle), for per-vertex or per-triangle
// arrays of the wrong length, for a tree that does not fit the scene, and for a scene
// too large for 32-bit offsets.
MemoryImage build_memory_image(const Scene& scene, const KdTree& tree, IsectMode mode);

// Checks every header field, section offset and size, count, kd child index and leaf
// primitive range; returns where things are. Throws rpu::Error naming `source`, the
// section and the byte offset of the first problem.
ImageLayout validate_memory_image(std::span<const std::uint8_t> bytes, const std::string& source);

void save_memory_image(const MemoryImage& image, const std::filesystem::path& file);
MemoryImage load_memory_image(const std::filesystem::path& file);  // reads; validate separately

// The shader id a material record holds is the index of the material's shader name in
// this list: the distinct names in order of first use over scene.materials. The image
// holds no strings, so whoever builds the shader table uses this same list.
std::vector<std::string> shader_names(const Scene& scene);

// The section's name in spec/memory_map.toml [section_id] ("kd_nodes"), or "section
// <id>" for an id the spec does not define; validation messages use it.
std::string section_name(std::uint32_t id);

}  // namespace rpu
