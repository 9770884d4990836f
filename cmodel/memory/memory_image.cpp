#include "memory/memory_image.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/output_file.hpp"
#include "memory/image_sections.hpp"
#include "memory/little_endian.hpp"
#include "scene/geometry.hpp"

namespace rpu {
namespace {

using namespace image_detail;

// Converts a double scene parameter to the image's fp32; a value that fp32 cannot hold
// would silently become infinity, so it is an error naming what it belongs to.
float to_fp32(double v, const std::string& source, std::string_view what) {
  if (!(std::abs(v) <= static_cast<double>(std::numeric_limits<float>::max()))) {
    throw Error(fmt::format("{}: {} = {} does not fit fp32", source, what, v));
  }
  return static_cast<float>(v);
}

glm::vec4 to_float4(const glm::dvec3& v, const std::string& source, std::string_view what) {
  return {to_fp32(v.x, source, what), to_fp32(v.y, source, what), to_fp32(v.z, source, what), 0.0f};
}

// Woop's unit-triangle transform (Woop, Schmittler, Slusallek 2005, section 4.2): the
// affine map T(x, y, z) = A + x (B - A) + y (C - A) + z N sends the unit triangle
// (0,0,0), (1,0,0), (0,1,0) to A, B, C; its inverse is (u, v, w) = L (p - A) with
// L = [B - A, C - A, N]^-1. The record holds L's rows in the xyz of its three float4 and
// A in their w (row i's w = A[i]), so that the unit measures from a vertex: a stored
// translation -L A, rounded to fp32, would misplace the plane by an ulp of the scene's
// coordinates, and t with it. N is the unit normal: then row 2 is N itself and w the
// signed distance from the plane, whose size does not depend on the triangle's area (an
// unnormalised cross product would scale row 2 by 1/area, which overflows fp32 for tiny
// triangles); u and v, and the hit distance t = -w(origin) / w(direction), are the same
// either way. Computed in double from the fp32 vertices and rounded to fp32 once.
std::array<glm::vec4, 3> woop_rows(const glm::vec3& a32, const glm::vec3& b32, const glm::vec3& c32,
                                   const std::string& source, std::size_t triangle) {
  const glm::dvec3 a(a32), b(b32), c(c32);
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const glm::dvec3 cross = glm::cross(e1, e2);
  const glm::dvec3 n = cross / glm::length(cross);
  const glm::dmat3 inverse = glm::inverse(glm::dmat3(e1, e2, n));  // columns e1, e2, n
  std::array<glm::vec4, 3> rows;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec4 m(inverse[0][i], inverse[1][i], inverse[2][i], a[i]);
    for (int k = 0; k < 4; ++k) {
      if (!(std::abs(m[k]) <= static_cast<double>(std::numeric_limits<float>::max()))) {
        throw Error(fmt::format(
            "{}: triangle {} (vertices ({}, {}, {}), ({}, {}, {}), ({}, {}, {})): its Woop transform is not "
            "finite in fp32 (a degenerate triangle?); drop it or use the watertight intersection mode",
            source, triangle, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z));
      }
      rows[static_cast<std::size_t>(i)][k] = static_cast<float>(m[k]);
    }
  }
  return rows;
}

// The watertight record: the vertices A, B, C, and in their w components the unit
// normal (x in A.w, y in B.w, z in C.w), from which the intersection unit computes t as
// n.(A - O) / n.D (docs/traversal.md §5): a distance whose rounding error is relative to
// t, and linear in the coordinates. Computed in double from the fp32 vertices and
// rounded once; a zero-area triangle gets n = 0, which no ray hits (t is not a number).
std::array<glm::vec4, 3> watertight_rows(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 cross = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  const double length = glm::length(cross);
  const glm::vec3 n = length > 0.0 ? glm::vec3(cross / length) : glm::vec3(0.0f);
  return {glm::vec4(a, n.x), glm::vec4(b, n.y), glm::vec4(c, n.z)};
}

std::uint32_t light_kind_id(LightKind kind) {
  switch (kind) {
    case LightKind::kPoint:
      return spec::memory::kLightKindPoint;
    case LightKind::kDirectional:
      return spec::memory::kLightKindDirectional;
    case LightKind::kArea:
      return spec::memory::kLightKindArea;
  }
  throw Error("unknown light kind");
}

// The scene's arrays must agree with each other before anything indexes them.
void check_scene(const Scene& scene) {
  const std::string& src = scene.source;
  const std::size_t vertices = scene.positions.size();
  if (scene.material_ids.size() != scene.triangles.size()) {
    throw Error(fmt::format("{}: {} material ids for {} triangles", src, scene.material_ids.size(),
                            scene.triangles.size()));
  }
  if (!scene.normals.empty() && scene.normals.size() != vertices) {
    throw Error(fmt::format("{}: {} normals for {} vertices", src, scene.normals.size(), vertices));
  }
  if (!scene.uvs.empty() && scene.uvs.size() != vertices) {
    throw Error(fmt::format("{}: {} uvs for {} vertices", src, scene.uvs.size(), vertices));
  }
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 t = scene.triangles[i];
    if (t.x >= vertices || t.y >= vertices || t.z >= vertices) {
      throw Error(fmt::format("{}: triangle {} uses vertex {} of {}", src, i, std::max({t.x, t.y, t.z}),
                              vertices));
    }
    if (scene.material_ids[i] >= scene.materials.size()) {
      throw Error(fmt::format("{}: triangle {} uses material {} of {}", src, i, scene.material_ids[i],
                              scene.materials.size()));
    }
  }
}

}  // namespace

std::vector<std::string> shader_names(const Scene& scene) {
  std::vector<std::string> names;
  for (const Material& m : scene.materials) {
    if (std::find(names.begin(), names.end(), m.shader) == names.end()) names.push_back(m.shader);
  }
  return names;
}

std::string section_name(std::uint32_t id) {
  const SectionKind* s = find_section(id);
  return s ? std::string(s->name) : fmt::format("section {}", id);
}

MemoryImage build_memory_image(const Scene& scene, const KdTree& tree, IsectMode mode) {
  namespace mm = spec::memory;
  check_scene(scene);
  const std::string& src = scene.source;

  // Record counts per section, in kSections order.
  const std::array<std::uint64_t, kSections.size()> counts{
      1, tree.nodes.size(), tree.prim_refs.size(), scene.triangles.size(), scene.normals.size(),
      scene.uvs.size(), scene.triangles.size(), scene.materials.size(), scene.lights.size(), 1,
      scene.positions.size()};
  MemoryImage image;
  std::array<std::uint64_t, kSections.size()> offsets{};
  std::uint64_t end = align_up(section_table_end(kSections.size()));
  for (std::size_t s = 0; s < kSections.size(); ++s) {
    const std::uint32_t record = kSections[s].record_bytes ? kSections[s].record_bytes : isect_record_bytes(mode);
    offsets[s] = align_up(end);
    end = offsets[s] + counts[s] * record;
  }
  if (end > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(fmt::format("{}: the memory image would be {} bytes; 32-bit offsets address at most 4 GiB",
                            src, end));
  }
  image.bytes.assign(end, 0);
  const std::span<std::uint8_t> out(image.bytes);

  store_u32(out, mm::kHeaderMagicAt, mm::kImageMagic);
  store_u32(out, mm::kHeaderVersionAt, mm::kImageVersion);
  store_u32(out, mm::kHeaderTotalBytesAt, static_cast<std::uint32_t>(end));
  store_u32(out, mm::kHeaderSectionCountAt, static_cast<std::uint32_t>(kSections.size()));
  for (std::size_t s = 0; s < kSections.size(); ++s) {
    const std::size_t e = mm::kHeaderBytes + s * mm::kSectionEntryBytes;
    const std::uint32_t record = kSections[s].record_bytes ? kSections[s].record_bytes : isect_record_bytes(mode);
    store_u32(out, e + mm::kSectionEntryIdAt, kSections[s].id);
    store_u32(out, e + mm::kSectionEntryOffsetAt, static_cast<std::uint32_t>(offsets[s]));
    store_u32(out, e + mm::kSectionEntryBytesAt, static_cast<std::uint32_t>(counts[s] * record));
    store_u32(out, e + mm::kSectionEntryCountAt, static_cast<std::uint32_t>(counts[s]));
  }
  const auto at = [&](std::uint32_t id) {
    return static_cast<std::size_t>(offsets[static_cast<std::size_t>(find_section(id) - kSections.data())]);
  };

  // scene
  {
    const std::size_t o = at(mm::kSectionIdScene);
    const Bounds box = scene_bounds(scene);
    const double diagonal = box.empty() ? 0.0 : glm::length(box.hi - box.lo);
    store_float4(out, o + mm::kSceneRecordBoundsLoAt, glm::vec4(tree.bounds_lo, 0.0f));
    store_float4(out, o + mm::kSceneRecordBoundsHiAt, glm::vec4(tree.bounds_hi, 0.0f));
    store_float4(out, o + mm::kSceneRecordBackgroundAt, to_float4(scene.background, src, "background"));
    store_u32(out, o + mm::kSceneRecordTriangleCountAt, static_cast<std::uint32_t>(scene.triangles.size()));
    store_u32(out, o + mm::kSceneRecordVertexCountAt, static_cast<std::uint32_t>(scene.positions.size()));
    store_u32(out, o + mm::kSceneRecordIsectModeAt, static_cast<std::uint32_t>(mode));
    store_f32(out, o + mm::kSceneRecordRayEpsilonAt, to_fp32(1e-4 * diagonal, src, "ray epsilon"));
    store_u32(out, o + mm::kSceneRecordMaterialCountAt, static_cast<std::uint32_t>(scene.materials.size()));
    store_u32(out, o + mm::kSceneRecordLightCountAt, static_cast<std::uint32_t>(scene.lights.size()));
    store_u32(out, o + mm::kSceneRecordKdScaleExponentAt, static_cast<std::uint32_t>(tree.scale_exponent));
    store_u32(out, o + mm::kSceneRecordRayOffsetShiftAt, static_cast<std::uint32_t>(fp::kFp32.fraction_bits - tree.format.fraction_bits));
  }
  for (std::size_t i = 0, o = at(mm::kSectionIdKdNodes); i < tree.nodes.size(); ++i, o += mm::kKdNodeBytes) {
    store_u32(out, o + mm::kKdNodeWord0At, tree.nodes[i].word0);
    store_u32(out, o + mm::kKdNodeWord1At, tree.nodes[i].word1);
  }
  for (std::size_t i = 0, o = at(mm::kSectionIdPrimRefs); i < tree.prim_refs.size(); ++i, o += mm::kPrimRefBytes) {
    store_u32(out, o, tree.prim_refs[i]);
  }
  const std::size_t isect = at(mm::kSectionIdIsectRecords), tris = at(mm::kSectionIdTriangles);
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 t = scene.triangles[i];
    // The records hold the triangle in the tree's kd space.
    const int kd = tree.scale_exponent;
    const glm::vec3 a = to_kd_space(scene.positions[t.x], kd), b = to_kd_space(scene.positions[t.y], kd),
                    c = to_kd_space(scene.positions[t.z], kd);
    const std::array<glm::vec4, 3> rows = mode == IsectMode::kWoop ? woop_rows(a, b, c, src, i)
                                                                     : watertight_rows(a, b, c);
    const std::size_t o = isect + i * isect_record_bytes(mode);
    store_float4(out, o + mm::kTriangleRecordRow0At, rows[0]);
    store_float4(out, o + mm::kTriangleRecordRow1At, rows[1]);
    store_float4(out, o + mm::kTriangleRecordRow2At, rows[2]);
    const std::size_t p = tris + i * mm::kTriangleBytes;
    store_u32(out, p + mm::kTriangleAAt, t.x);
    store_u32(out, p + mm::kTriangleBAt, t.y);
    store_u32(out, p + mm::kTriangleCAt, t.z);
    store_u32(out, p + mm::kTriangleMaterialAt, scene.material_ids[i]);
  }
  for (std::size_t i = 0, o = at(mm::kSectionIdVertexPositions); i < scene.positions.size(); ++i) {
    store_float4(out, o + i * mm::kVertexPositionBytes, glm::vec4(scene.positions[i], 0.0f));
  }
  for (std::size_t i = 0, o = at(mm::kSectionIdVertexNormals); i < scene.normals.size(); ++i) {
    store_float4(out, o + i * mm::kVertexNormalBytes, glm::vec4(scene.normals[i], 0.0f));
  }
  for (std::size_t i = 0, o = at(mm::kSectionIdVertexUvs); i < scene.uvs.size(); ++i) {
    store_f32(out, o + i * mm::kVertexUvBytes, scene.uvs[i].x);
    store_f32(out, o + i * mm::kVertexUvBytes + 4, scene.uvs[i].y);
  }
  const std::vector<std::string> shaders = shader_names(scene);
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    const std::size_t o = at(mm::kSectionIdMaterials) + i * mm::kMaterialBytes;
    const std::string what = fmt::format("material {} (\"{}\")", i, m.name);
    store_float4(out, o + mm::kMaterialAmbientAt, to_float4(m.ambient, src, what + " ambient"));
    store_float4(out, o + mm::kMaterialDiffuseAt, to_float4(m.diffuse, src, what + " diffuse"));
    store_float4(out, o + mm::kMaterialSpecularAt, to_float4(m.specular, src, what + " specular"));
    store_f32(out, o + mm::kMaterialShininessAt, to_fp32(m.shininess, src, what + " shininess"));
    store_f32(out, o + mm::kMaterialReflectanceAt, to_fp32(m.reflectance, src, what + " reflectance"));
    store_f32(out, o + mm::kMaterialTransmittanceAt, to_fp32(m.transmittance, src, what + " transmittance"));
    store_f32(out, o + mm::kMaterialIorAt, to_fp32(m.ior, src, what + " ior"));
    store_f32(out, o + mm::kMaterialRoughnessAt, to_fp32(m.roughness, src, what + " roughness"));
    const auto shader = std::find(shaders.begin(), shaders.end(), m.shader) - shaders.begin();
    store_u32(out, o + mm::kMaterialShaderAt, static_cast<std::uint32_t>(shader));
  }
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    const std::size_t o = at(mm::kSectionIdLights) + i * mm::kLightBytes;
    const std::string what = fmt::format("light {}", i);
    store_u32(out, o + mm::kLightKindAt, light_kind_id(l.kind));
    store_float4(out, o + mm::kLightColorAt, to_float4(l.color, src, what + " color"));
    store_float4(out, o + mm::kLightPositionAt, to_float4(l.position, src, what + " position"));
    store_float4(out, o + mm::kLightDirectionAt, to_float4(l.direction, src, what + " direction"));
    store_float4(out, o + mm::kLightEdgeUAt, to_float4(l.edge_u, src, what + " edge_u"));
    store_float4(out, o + mm::kLightEdgeVAt, to_float4(l.edge_v, src, what + " edge_v"));
  }
  {
    const Camera& c = scene.camera;
    const std::size_t o = at(mm::kSectionIdCamera);
    store_float4(out, o + mm::kCameraPositionAt, to_float4(c.position, src, "camera position"));
    store_float4(out, o + mm::kCameraLookAtAt, to_float4(c.look_at, src, "camera look_at"));
    store_float4(out, o + mm::kCameraUpAt, to_float4(c.up, src, "camera up"));
    store_f32(out, o + mm::kCameraVfovAt, to_fp32(c.vfov_degrees, src, "camera vfov"));
    store_f32(out, o + mm::kCameraApertureAt, to_fp32(c.aperture_radius, src, "camera aperture"));
    store_f32(out, o + mm::kCameraFocusDistanceAt, to_fp32(c.focus_distance, src, "camera focus distance"));
  }

  // The writer and the reader must agree; a tree that does not fit the scene (a prim
  // ref past the triangles, a bad child index) is caught here, naming the scene.
  validate_memory_image(image.bytes, src);
  return image;
}

void save_memory_image(const MemoryImage& image, const std::filesystem::path& file) {
  OutputFile out(file);
  out.stream().write(reinterpret_cast<const char*>(image.bytes.data()), static_cast<std::streamsize>(image.bytes.size()));
  out.commit();
}

MemoryImage load_memory_image(const std::filesystem::path& file) {
  check_input_file(file, "the memory image");
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec || size > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(fmt::format("{}: cannot read the memory image ({})", file.string(),
                            ec ? ec.message() : std::string("larger than 4 GiB, which 32-bit offsets address")));
  }
  std::ifstream in(file, std::ios::binary);
  MemoryImage image;
  image.bytes.resize(static_cast<std::size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(image.bytes.data()), static_cast<std::streamsize>(size))) {
    throw Error(fmt::format("{}: cannot read the memory image", file.string()));
  }
  return image;
}

}  // namespace rpu
