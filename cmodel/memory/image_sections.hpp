#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

namespace rpu::image_detail {

namespace mm = spec::memory;

// Every section the spec defines, in the order the writer lays them out: its id, its
// name in messages, its record size (0: depends on the intersection mode) and where
// ImageLayout keeps it. All of them are required, exactly once.
struct SectionKind {
  std::uint32_t id;
  std::string_view name;
  std::uint32_t record_bytes;
  ImageSection ImageLayout::*layout;
};

inline constexpr std::array<SectionKind, 11> kSections{{
    {mm::kSectionIdScene, "scene", mm::kSceneRecordBytes, &ImageLayout::scene},
    {mm::kSectionIdKdNodes, "kd_nodes", mm::kKdNodeBytes, &ImageLayout::kd_nodes},
    {mm::kSectionIdPrimRefs, "prim_refs", mm::kPrimRefBytes, &ImageLayout::prim_refs},
    {mm::kSectionIdIsectRecords, "isect_records", 0, &ImageLayout::isect_records},
    {mm::kSectionIdVertexNormals, "vertex_normals", mm::kVertexNormalBytes, &ImageLayout::vertex_normals},
    {mm::kSectionIdVertexUvs, "vertex_uvs", mm::kVertexUvBytes, &ImageLayout::vertex_uvs},
    {mm::kSectionIdTriangles, "triangles", mm::kTriangleBytes, &ImageLayout::triangles},
    {mm::kSectionIdMaterials, "materials", mm::kMaterialBytes, &ImageLayout::materials},
    {mm::kSectionIdLights, "lights", mm::kLightBytes, &ImageLayout::lights},
    {mm::kSectionIdCamera, "camera", mm::kCameraBytes, &ImageLayout::camera},
    {mm::kSectionIdVertexPositions, "vertex_positions", mm::kVertexPositionBytes, &ImageLayout::vertex_positions},
}};

inline const SectionKind* find_section(std::uint32_t id) {
  for (const SectionKind& s : kSections) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

// Where the section table ends, for `count` entries.
inline std::uint64_t section_table_end(std::uint64_t count) {
  return mm::kHeaderBytes + count * mm::kSectionEntryBytes;
}

inline std::uint64_t align_up(std::uint64_t at) {
  const std::uint64_t a = mm::kImageSectionAlignment;
  return (at + a - 1) / a * a;
}

}  // namespace rpu::image_detail
