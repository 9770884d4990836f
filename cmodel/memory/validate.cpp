#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "fp/format.hpp"
#include "kdtree/kdtree.hpp"
#include "memory/image_sections.hpp"
#include "memory/little_endian.hpp"
#include "memory/memory_image.hpp"

namespace rpu {
namespace {

using namespace image_detail;

// Reads an untrusted image. Every read is preceded by a bounds check in 64-bit
// arithmetic, so no field value can make it read outside `bytes`.
class Validator {
 public:
  Validator(std::span<const std::uint8_t> bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  // "<source>: <section>: <item> at offset 0x<offset>: <problem>"
  [[noreturn]] void fail(std::string_view section, std::string_view item, std::uint64_t offset,
                         std::string_view problem) const {
    throw Error(fmt::format("{}: {}: {} at offset {:#x}: {}", source_, section, item, offset, problem));
  }

  std::uint32_t u32(std::uint64_t at) const { return load_u32(bytes_, static_cast<std::size_t>(at)); }
  float f32(std::uint64_t at) const { return load_f32(bytes_, static_cast<std::size_t>(at)); }

  ImageLayout run();

 private:
  void read_header();
  void read_section_table();
  void read_scene();
  void check_kd_nodes() const;
  void check_prim_refs() const;
  void check_triangles() const;
  void check_isect_records() const;
  void check_lights() const;
  void check_finite_vec3(std::string_view section, std::string_view item, std::uint64_t at) const;

  std::span<const std::uint8_t> bytes_;
  const std::string& source_;
  ImageLayout layout_;
  std::uint32_t section_count_ = 0;
};

void Validator::read_header() {
  namespace mm = spec::memory;
  if (bytes_.size() < mm::kHeaderBytes) {
    fail("header", "image", 0,
         fmt::format("{} bytes, shorter than the {}-byte header (truncated)", bytes_.size(), mm::kHeaderBytes));
  }
  if (const std::uint32_t magic = u32(mm::kHeaderMagicAt); magic != mm::kImageMagic) {
    fail("header", "magic", mm::kHeaderMagicAt,
         fmt::format("{:#010x} is not {:#010x} (\"RPU1\"); not an rpu memory image", magic, mm::kImageMagic));
  }
  if (const std::uint32_t version = u32(mm::kHeaderVersionAt); version != mm::kImageVersion) {
    fail("header", "version", mm::kHeaderVersionAt,
         fmt::format("version {}, this model reads version {} (rebuild the image)", version, mm::kImageVersion));
  }
  layout_.total_bytes = u32(mm::kHeaderTotalBytesAt);
  if (layout_.total_bytes > bytes_.size()) {
    fail("header", "total_bytes", mm::kHeaderTotalBytesAt,
         fmt::format("the header says {} bytes, the image has {} (truncated)", layout_.total_bytes, bytes_.size()));
  }
  if (layout_.total_bytes < bytes_.size()) {
    fail("header", "total_bytes", mm::kHeaderTotalBytesAt,
         fmt::format("the header says {} bytes, the image has {} (trailing bytes)", layout_.total_bytes,
                     bytes_.size()));
  }
  section_count_ = u32(mm::kHeaderSectionCountAt);
  if (section_table_end(section_count_) > layout_.total_bytes) {
    fail("header", "section_count", mm::kHeaderSectionCountAt,
         fmt::format("a table of {} sections would end at {:#x}, past the end of the image ({:#x})",
                     section_count_, section_table_end(section_count_), layout_.total_bytes));
  }
}

void Validator::read_section_table() {
  namespace mm = spec::memory;
  const std::uint64_t table_end = section_table_end(section_count_);
  std::array<std::uint64_t, kSections.size()> entry_of{};  // entry index + 1, 0 = absent
  struct Extent {
    std::uint64_t offset, end;
    std::string_view name;
  };
  std::vector<Extent> extents;
  for (std::uint32_t k = 0; k < section_count_; ++k) {
    const std::uint64_t e = mm::kHeaderBytes + std::uint64_t{k} * mm::kSectionEntryBytes;
    const std::uint32_t id = u32(e + mm::kSectionEntryIdAt);
    const SectionKind* kind = find_section(id);
    if (!kind) fail("section_table", fmt::format("entry {}", k), e, fmt::format("unknown section id {}", id));
    const auto index = static_cast<std::size_t>(kind - kSections.data());
    if (entry_of[index]) {
      fail("section_table", fmt::format("entry {}", k), e,
           fmt::format("a second {} section (the first is entry {})", kind->name, entry_of[index] - 1));
    }
    entry_of[index] = k + 1u;
    ImageSection& s = layout_.*(kind->layout);
    s.offset = u32(e + mm::kSectionEntryOffsetAt);
    s.bytes = u32(e + mm::kSectionEntryBytesAt);
    s.count = u32(e + mm::kSectionEntryCountAt);
    const std::uint64_t end = std::uint64_t{s.offset} + s.bytes;
    if (s.offset % mm::kImageSectionAlignment) {
      fail(kind->name, "section", s.offset, fmt::format("not aligned to {} bytes", mm::kImageSectionAlignment));
    }
    if (s.offset < table_end) {
      fail(kind->name, "section", s.offset,
           fmt::format("starts inside the header and section table, which end at {:#x}", table_end));
    }
    if (end > layout_.total_bytes) {
      fail(kind->name, "section", s.offset,
           fmt::format("its {} bytes run past the end of the image ({:#x}) to {:#x}", s.bytes,
                       layout_.total_bytes, end));
    }
    // Intersection records are checked once the scene record gives the mode.
    if (kind->record_bytes && std::uint64_t{s.count} * kind->record_bytes != s.bytes) {
      fail(kind->name, "section", s.offset,
           fmt::format("{} bytes is not {} records of {} bytes", s.bytes, s.count, kind->record_bytes));
    }
    if (s.bytes) extents.push_back({s.offset, end, kind->name});
  }
  for (std::size_t i = 0; i < kSections.size(); ++i) {
    if (!entry_of[i]) {
      fail(kSections[i].name, "section table", mm::kHeaderBytes, "the section is missing");
    }
  }
  std::sort(extents.begin(), extents.end(), [](const Extent& a, const Extent& b) { return a.offset < b.offset; });
  for (std::size_t i = 1; i < extents.size(); ++i) {
    if (extents[i].offset < extents[i - 1].end) {
      fail(extents[i].name, "section", extents[i].offset,
           fmt::format("overlaps {} ({:#x}..{:#x})", extents[i - 1].name, extents[i - 1].offset,
                       extents[i - 1].end));
    }
  }
}

void Validator::check_finite_vec3(std::string_view section, std::string_view item, std::uint64_t at) const {
  for (int k = 0; k < 3; ++k) {
    if (const float v = f32(at + 4u * static_cast<unsigned>(k)); !std::isfinite(v)) {
      fail(section, item, at, fmt::format("component {} is {}", k, v));
    }
  }
}

void Validator::read_scene() {
  namespace mm = spec::memory;
  const ImageSection& s = layout_.scene;
  if (s.count != 1) fail("scene", "section", s.offset, fmt::format("{} records, expected 1", s.count));
  if (layout_.camera.count != 1) {
    fail("camera", "section", layout_.camera.offset, fmt::format("{} records, expected 1", layout_.camera.count));
  }
  const std::uint64_t o = s.offset;
  check_finite_vec3("scene", "bounds_lo", o + mm::kSceneRecordBoundsLoAt);
  check_finite_vec3("scene", "bounds_hi", o + mm::kSceneRecordBoundsHiAt);
  const glm::vec4 lo = load_float4(bytes_, o + mm::kSceneRecordBoundsLoAt);
  const glm::vec4 hi = load_float4(bytes_, o + mm::kSceneRecordBoundsHiAt);
  layout_.bounds_lo = glm::vec3(lo);
  layout_.bounds_hi = glm::vec3(hi);
  layout_.background = glm::vec3(load_float4(bytes_, o + mm::kSceneRecordBackgroundAt));
  layout_.triangle_count = u32(o + mm::kSceneRecordTriangleCountAt);
  layout_.vertex_count = u32(o + mm::kSceneRecordVertexCountAt);
  layout_.material_count = u32(o + mm::kSceneRecordMaterialCountAt);
  layout_.light_count = u32(o + mm::kSceneRecordLightCountAt);
  layout_.ray_epsilon = f32(o + mm::kSceneRecordRayEpsilonAt);
  const std::uint32_t mode = u32(o + mm::kSceneRecordIsectModeAt);
  if (mode != mm::kIsectModeWoop && mode != mm::kIsectModeWatertight) {
    fail("scene", "isect_mode", o + mm::kSceneRecordIsectModeAt,
         fmt::format("unknown intersection mode {} (woop = {}, watertight = {})", mode, mm::kIsectModeWoop,
                     mm::kIsectModeWatertight));
  }
  layout_.isect_mode = static_cast<IsectMode>(mode);
  const auto kd_scale = static_cast<std::int32_t>(u32(o + mm::kSceneRecordKdScaleExponentAt));
  if (kd_scale < kKdMinScaleExponent || kd_scale > kKdMaxScaleExponent) {
    fail("scene", "kd_scale_exponent", o + mm::kSceneRecordKdScaleExponentAt,
         fmt::format("{} is outside [{}, {}], the exponents of normal fp32 numbers", kd_scale, kKdMinScaleExponent,
                     kKdMaxScaleExponent));
  }
  layout_.kd_scale_exponent = kd_scale;
  if (!(layout_.ray_epsilon >= 0.0f && std::isfinite(layout_.ray_epsilon))) {
    fail("scene", "ray_epsilon", o + mm::kSceneRecordRayEpsilonAt,
         fmt::format("{} is not a finite number >= 0", layout_.ray_epsilon));
  }
  layout_.ray_offset_shift = u32(o + mm::kSceneRecordRayOffsetShiftAt);
  // fp32's fraction bits less the format's, which keeps at least one
  constexpr std::uint32_t kMostShift = fp::kFp32.fraction_bits - 1;
  if (layout_.ray_offset_shift > kMostShift) {
    fail("scene", "ray_offset_shift", o + mm::kSceneRecordRayOffsetShiftAt,
         fmt::format("{} is outside [0, {}] (23 - the format's fraction bits)", layout_.ray_offset_shift, kMostShift));
  }
  const auto count_matches = [&](const ImageSection& section, std::string_view name, std::uint32_t want,
                                 std::string_view what, std::uint32_t field_at) {
    if (section.count != want) {
      fail(name, "section", section.offset,
           fmt::format("{} records, but the scene record ({:#x}) says {} {}", section.count, o + field_at, want,
                       what));
    }
  };
  count_matches(layout_.triangles, "triangles", layout_.triangle_count, "triangles", mm::kSceneRecordTriangleCountAt);
  count_matches(layout_.isect_records, "isect_records", layout_.triangle_count, "triangles",
                mm::kSceneRecordTriangleCountAt);
  count_matches(layout_.materials, "materials", layout_.material_count, "materials", mm::kSceneRecordMaterialCountAt);
  count_matches(layout_.lights, "lights", layout_.light_count, "lights", mm::kSceneRecordLightCountAt);
  count_matches(layout_.vertex_positions, "vertex_positions", layout_.vertex_count, "vertices",
                mm::kSceneRecordVertexCountAt);
  if (layout_.vertex_normals.count) {
    count_matches(layout_.vertex_normals, "vertex_normals", layout_.vertex_count, "vertices",
                  mm::kSceneRecordVertexCountAt);
  }
  if (layout_.vertex_uvs.count) {
    count_matches(layout_.vertex_uvs, "vertex_uvs", layout_.vertex_count, "vertices", mm::kSceneRecordVertexCountAt);
  }
  const ImageSection& r = layout_.isect_records;
  const std::uint32_t record = isect_record_bytes(layout_.isect_mode);
  if (std::uint64_t{r.count} * record != r.bytes) {
    fail("isect_records", "section", r.offset,
         fmt::format("{} bytes is not {} records of {} bytes", r.bytes, r.count, record));
  }
}

void Validator::check_kd_nodes() const {
  namespace mm = spec::memory;
  const ImageSection& s = layout_.kd_nodes;
  if (s.count == 0) fail("kd_nodes", "section", s.offset, "no nodes (the root is node 0)");
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::uint64_t at = s.offset + std::uint64_t{i} * mm::kKdNodeBytes;
    const KdNode node{u32(at + mm::kKdNodeWord0At), u32(at + mm::kKdNodeWord1At)};
    const std::string item = fmt::format("node {}", i);
    // Two kind bits: axes 0, 1, 2 and the leaf kind 3 use every value, so each node
    // is either an inner node or a leaf and only its fields need checking.
    if (node.is_leaf()) {
      const std::uint64_t end = std::uint64_t{node.first_prim_ref()} + node.prim_count();
      if (end > layout_.prim_refs.count) {
        fail("kd_nodes", item, at,
             fmt::format("leaf primitives [{}, {}) run past the primitive list ({} entries)",
                         node.first_prim_ref(), end, layout_.prim_refs.count));
      }
      continue;
    }
    if (std::isnan(node.split())) fail("kd_nodes", item, at, "the split value is NaN");
    // Children after their parent (below child = index + 1, above child > index):
    // traversal can never revisit a node, so no image makes it loop.
    if (node.above_child() <= i) {
      fail("kd_nodes", item, at,
           fmt::format("above child {} does not come after the node (a cycle)", node.above_child()));
    }
    if (node.above_child() >= s.count) {
      fail("kd_nodes", item, at, fmt::format("above child {} out of range ({} nodes)", node.above_child(), s.count));
    }
    if (std::uint64_t{i} + 1 >= s.count) {
      fail("kd_nodes", item, at, fmt::format("below child {} out of range ({} nodes)", std::uint64_t{i} + 1, s.count));
    }
  }
}

void Validator::check_prim_refs() const {
  const ImageSection& s = layout_.prim_refs;
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::uint64_t at = s.offset + std::uint64_t{i} * spec::memory::kPrimRefBytes;
    if (const std::uint32_t t = u32(at); t >= layout_.triangle_count) {
      fail("prim_refs", fmt::format("entry {}", i), at,
           fmt::format("triangle {} out of range ({} triangles)", t, layout_.triangle_count));
    }
  }
}

void Validator::check_triangles() const {
  namespace mm = spec::memory;
  const ImageSection& s = layout_.triangles;
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::uint64_t at = s.offset + std::uint64_t{i} * mm::kTriangleBytes;
    for (const std::uint32_t field : {mm::kTriangleAAt, mm::kTriangleBAt, mm::kTriangleCAt}) {
      if (const std::uint32_t v = u32(at + field); v >= layout_.vertex_count) {
        fail("triangles", fmt::format("triangle {}", i), at,
             fmt::format("vertex {} out of range ({} vertices)", v, layout_.vertex_count));
      }
    }
    if (const std::uint32_t m = u32(at + mm::kTriangleMaterialAt); m >= layout_.material_count) {
      fail("triangles", fmt::format("triangle {}", i), at,
           fmt::format("material {} out of range ({} materials)", m, layout_.material_count));
    }
  }
}

void Validator::check_isect_records() const {
  namespace mm = spec::memory;
  const ImageSection& s = layout_.isect_records;
  const std::uint32_t record = isect_record_bytes(layout_.isect_mode);
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::uint64_t at = s.offset + std::uint64_t{i} * record;
    for (const std::uint32_t row : {mm::kTriangleRecordRow0At, mm::kTriangleRecordRow1At, mm::kTriangleRecordRow2At}) {
      // Both modes use all four components (watertight: a vertex and a normal component).
      for (int k = 0; k < 4; ++k) {
        if (const float v = f32(at + row + 4u * static_cast<unsigned>(k)); !std::isfinite(v)) {
          fail("isect_records", fmt::format("record {}", i), at, fmt::format("a component is {}", v));
        }
      }
    }
  }
}

void Validator::check_lights() const {
  namespace mm = spec::memory;
  const ImageSection& s = layout_.lights;
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::uint64_t at = s.offset + std::uint64_t{i} * mm::kLightBytes;
    if (const std::uint32_t kind = u32(at + mm::kLightKindAt);
        kind != mm::kLightKindPoint && kind != mm::kLightKindDirectional && kind != mm::kLightKindArea) {
      fail("lights", fmt::format("light {}", i), at, fmt::format("unknown light kind {}", kind));
    }
  }
}

ImageLayout Validator::run() {
  read_header();
  read_section_table();
  read_scene();
  check_kd_nodes();
  check_prim_refs();
  check_triangles();
  check_isect_records();
  check_lights();
  return layout_;
}

}  // namespace

ImageLayout validate_memory_image(std::span<const std::uint8_t> bytes, const std::string& source) {
  return Validator(bytes, source).run();
}

}  // namespace rpu
