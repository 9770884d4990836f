#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "kdtree/kdtree.hpp"
#include "scene/scene.hpp"

namespace rpu {

// How the intersection unit tests triangles, and so what an intersection record holds.
enum class IsectMode : std::uint32_t {
  kWoop = 0,        // Woop's unit-triangle transform: 3 float4 rows (RPU 2005)
  kWatertight = 1,  // Woop, Benthin, Wald 2013: the three vertices as float4
};

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
      lights, camera;
  glm::vec3 bounds_lo{0.0f}, bounds_hi{0.0f};  // the kd-tree's root box
  IsectMode isect_mode = IsectMode::kWoop;
  std::uint32_t triangle_count = 0;
  float ray_epsilon = 0.0f;
};

MemoryImage build_memory_image(const Scene& scene, const KdTree& tree, IsectMode mode);

// Checks every header field, section offset and size, count, kd child index and leaf
// primitive range; returns where things are. Throws rpu::Error naming `source`, the
// section and the byte offset of the first problem.
ImageLayout validate_memory_image(std::span<const std::uint8_t> bytes, const std::string& source);

void save_memory_image(const MemoryImage& image, const std::filesystem::path& file);
MemoryImage load_memory_image(const std::filesystem::path& file);  // reads; validate separately

}  // namespace rpu
