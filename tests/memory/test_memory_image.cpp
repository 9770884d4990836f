// The memory image: every field written where docs/memory-map.md says, read back;
// Woop records checked against geometry done here; every validation rule rejects a
// broken image with a message naming the file, section and offset.
#include <gtest/gtest.h>

#include <utility>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "memory/little_endian.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"
#include "tiny_scene.hpp"

namespace rpu {
namespace {

namespace mm = spec::memory;
namespace fs = std::filesystem;

std::string rejection(std::span<const std::uint8_t> bytes) {
  try {
    validate_memory_image(bytes, "bad.rpu");
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

// The image is rejected with a message containing every one of `parts`.
void expect_rejected(std::span<const std::uint8_t> bytes, std::initializer_list<std::string> parts) {
  const std::string message = rejection(bytes);
  for (const std::string& part : parts) {
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

// A valid Woop image over split_tree() and its layout; tests break one thing each.
struct Fixture : ::testing::Test {
  Scene scene = test::tiny_scene();
  std::vector<std::uint8_t> bytes = build_memory_image(scene, test::split_tree(), IsectMode::kWoop).bytes;
  ImageLayout layout = validate_memory_image(bytes, "good.rpu");

  std::span<std::uint8_t> out() { return bytes; }
  std::size_t entry(std::size_t index) const { return mm::kHeaderBytes + index * mm::kSectionEntryBytes; }
  // The table entry of the section with this id.
  std::size_t entry_of(std::uint32_t id) const {
    for (std::size_t k = 0;; ++k) {
      if (load_u32(bytes, entry(k) + mm::kSectionEntryIdAt) == id) return entry(k);
    }
  }
  std::size_t node(std::size_t i) const { return layout.kd_nodes.offset + i * mm::kKdNodeBytes; }
};

using MemoryImageRoundTrip = Fixture;

TEST_F(MemoryImageRoundTrip, SaveLoadValidateAndReadBackEveryField) {
  const fs::path file = fs::path(::testing::TempDir()) / "round_trip.rpu";
  save_memory_image(MemoryImage{bytes}, file);
  const MemoryImage loaded = load_memory_image(file);
  ASSERT_EQ(loaded.bytes, bytes);
  const ImageLayout l = validate_memory_image(loaded.bytes, file.string());
  const std::span<const std::uint8_t> in(loaded.bytes);

  // Header: "RPU1" in the first four bytes on any host.
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(in.data()), 4), "RPU1");
  EXPECT_EQ(load_u32(in, mm::kHeaderVersionAt), mm::kImageVersion);
  EXPECT_EQ(load_u32(in, mm::kHeaderTotalBytesAt), in.size());
  EXPECT_EQ(l.total_bytes, in.size());

  EXPECT_EQ(l.triangle_count, 4u);
  EXPECT_EQ(l.vertex_count, 6u);
  EXPECT_EQ(l.material_count, 3u);
  EXPECT_EQ(l.light_count, 3u);
  EXPECT_EQ(l.isect_mode, IsectMode::kWoop);
  EXPECT_EQ(l.bounds_lo, glm::vec3(-0.7f, -0.9f, -0.3f));
  EXPECT_EQ(l.bounds_hi, glm::vec3(1.5f, 1.2f, 2.5f));
  EXPECT_EQ(l.background, glm::vec3(0.05f, 0.1f, 0.2f));
  // The scene's vertices span (-0.7, -0.9, -0.3) .. (1.5, 1.2, 2.5).
  const double diagonal = std::sqrt(2.2 * 2.2 + 2.1 * 2.1 + 2.8 * 2.8);
  EXPECT_NEAR(l.ray_epsilon, 1e-4 * diagonal, 1e-10);
  EXPECT_EQ(l.ray_offset_shift, 0u);  // fp32: an ulp is bit 0 of the pattern
  for (const ImageSection* s : {&l.scene, &l.kd_nodes, &l.prim_refs, &l.isect_records, &l.vertex_normals,
                                &l.vertex_uvs, &l.triangles, &l.materials, &l.lights, &l.camera,
                                &l.vertex_positions}) {
    EXPECT_EQ(s->offset % mm::kImageSectionAlignment, 0u);
  }

  const KdTree tree = test::split_tree();
  ASSERT_EQ(l.kd_nodes.count, tree.nodes.size());
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const std::size_t at = l.kd_nodes.offset + i * mm::kKdNodeBytes;
    EXPECT_EQ(load_u32(in, at + mm::kKdNodeWord0At), tree.nodes[i].word0) << i;
    EXPECT_EQ(load_u32(in, at + mm::kKdNodeWord1At), tree.nodes[i].word1) << i;
  }
  EXPECT_EQ(load_f32(in, l.kd_nodes.offset + 4), 0.5f);
  ASSERT_EQ(l.prim_refs.count, tree.prim_refs.size());
  for (std::size_t i = 0; i < tree.prim_refs.size(); ++i) {
    EXPECT_EQ(load_u32(in, l.prim_refs.offset + 4 * i), tree.prim_refs[i]);
  }
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const std::size_t at = l.triangles.offset + i * mm::kTriangleBytes;
    EXPECT_EQ(load_u32(in, at + mm::kTriangleAAt), scene.triangles[i].x);
    EXPECT_EQ(load_u32(in, at + mm::kTriangleBAt), scene.triangles[i].y);
    EXPECT_EQ(load_u32(in, at + mm::kTriangleCAt), scene.triangles[i].z);
    EXPECT_EQ(load_u32(in, at + mm::kTriangleMaterialAt), scene.material_ids[i]);
  }
  ASSERT_EQ(l.vertex_positions.count, scene.positions.size());
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    EXPECT_EQ(load_float4(in, l.vertex_positions.offset + i * mm::kVertexPositionBytes),
              glm::vec4(scene.positions[i], 0));
    EXPECT_EQ(load_float4(in, l.vertex_normals.offset + i * mm::kVertexNormalBytes), glm::vec4(scene.normals[i], 0));
    EXPECT_EQ(load_f32(in, l.vertex_uvs.offset + i * mm::kVertexUvBytes), scene.uvs[i].x);
    EXPECT_EQ(load_f32(in, l.vertex_uvs.offset + i * mm::kVertexUvBytes + 4), scene.uvs[i].y);
  }
  const std::uint32_t shader_ids[] = {0, 1, 0};  // "whitted", "mirror", "whitted"
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    const std::size_t at = l.materials.offset + i * mm::kMaterialBytes;
    EXPECT_EQ(load_float4(in, at + mm::kMaterialAmbientAt), glm::vec4(glm::vec3(m.ambient), 0));
    EXPECT_EQ(load_float4(in, at + mm::kMaterialDiffuseAt), glm::vec4(glm::vec3(m.diffuse), 0));
    EXPECT_EQ(load_float4(in, at + mm::kMaterialSpecularAt), glm::vec4(glm::vec3(m.specular), 0));
    EXPECT_EQ(load_f32(in, at + mm::kMaterialShininessAt), static_cast<float>(m.shininess));
    EXPECT_EQ(load_f32(in, at + mm::kMaterialReflectanceAt), static_cast<float>(m.reflectance));
    EXPECT_EQ(load_f32(in, at + mm::kMaterialTransmittanceAt), static_cast<float>(m.transmittance));
    EXPECT_EQ(load_f32(in, at + mm::kMaterialIorAt), static_cast<float>(m.ior));
    EXPECT_EQ(load_f32(in, at + mm::kMaterialRoughnessAt), static_cast<float>(m.roughness));
    EXPECT_EQ(load_u32(in, at + mm::kMaterialShaderAt), shader_ids[i]);
  }
  EXPECT_EQ(shader_names(scene), (std::vector<std::string>{"whitted", "mirror"}));
  const std::uint32_t kinds[] = {mm::kLightKindPoint, mm::kLightKindDirectional, mm::kLightKindArea};
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& li = scene.lights[i];
    const std::size_t at = l.lights.offset + i * mm::kLightBytes;
    EXPECT_EQ(load_u32(in, at + mm::kLightKindAt), kinds[i]);
    EXPECT_EQ(load_float4(in, at + mm::kLightColorAt), glm::vec4(glm::vec3(li.color), 0));
    EXPECT_EQ(load_float4(in, at + mm::kLightPositionAt), glm::vec4(glm::vec3(li.position), 0));
    EXPECT_EQ(load_float4(in, at + mm::kLightDirectionAt), glm::vec4(glm::vec3(li.direction), 0));
    EXPECT_EQ(load_float4(in, at + mm::kLightEdgeUAt), glm::vec4(glm::vec3(li.edge_u), 0));
    EXPECT_EQ(load_float4(in, at + mm::kLightEdgeVAt), glm::vec4(glm::vec3(li.edge_v), 0));
  }
  const Camera& c = scene.camera;
  EXPECT_EQ(load_float4(in, l.camera.offset + mm::kCameraPositionAt), glm::vec4(glm::vec3(c.position), 0));
  EXPECT_EQ(load_float4(in, l.camera.offset + mm::kCameraLookAtAt), glm::vec4(glm::vec3(c.look_at), 0));
  EXPECT_EQ(load_float4(in, l.camera.offset + mm::kCameraUpAt), glm::vec4(glm::vec3(c.up), 0));
  EXPECT_EQ(load_f32(in, l.camera.offset + mm::kCameraVfovAt), 35.0f);
  EXPECT_EQ(load_f32(in, l.camera.offset + mm::kCameraApertureAt), 0.05f);
  EXPECT_EQ(load_f32(in, l.camera.offset + mm::kCameraFocusDistanceAt), 6.5f);
}

// The rows' w hold A exactly, and their xyz, L, map B - A, C - A and N (the unit normal,
// computed here in double) to the unit triangle's corners (1, 0, 0), (0, 1, 0) and
// (0, 0, 1). L's entries were rounded to fp32 once, so each result is off by at most
// 2^-24 times the sum of the magnitudes of its terms (doubled for the rounding of the
// inverse itself); the products here are exact in double.
TEST_F(MemoryImageRoundTrip, WoopRecordsMapTheTriangleToTheUnitTriangle) {
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const std::size_t at = layout.isect_records.offset + i * mm::kTriangleRecordWoopBytes;
    const glm::dvec4 rows[3] = {glm::dvec4(load_float4(bytes, at + mm::kTriangleRecordRow0At)),
                                glm::dvec4(load_float4(bytes, at + mm::kTriangleRecordRow1At)),
                                glm::dvec4(load_float4(bytes, at + mm::kTriangleRecordRow2At))};
    const glm::dvec3 a(scene.positions[scene.triangles[i].x]), b(scene.positions[scene.triangles[i].y]),
        c(scene.positions[scene.triangles[i].z]);
    EXPECT_EQ(glm::dvec3(rows[0].w, rows[1].w, rows[2].w), a) << "triangle " << i;
    const glm::dvec3 cross(glm::cross(b - a, c - a));
    const glm::dvec3 n = cross / std::sqrt(glm::dot(cross, cross));
    const struct {
      glm::dvec3 p, want;
    } cases[] = {{b - a, {1, 0, 0}}, {c - a, {0, 1, 0}}, {n, {0, 0, 1}}};
    for (const auto& [p, want] : cases) {
      for (int r = 0; r < 3; ++r) {
        const glm::dvec4& m = rows[r];
        const double got = m.x * p.x + m.y * p.y + m.z * p.z;
        const double scale = std::abs(m.x * p.x) + std::abs(m.y * p.y) + std::abs(m.z * p.z);
        EXPECT_NEAR(got, want[r], 2.0 * 0x1p-24 * scale)
            << "triangle " << i << " row " << r << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
      }
    }
  }
}

TEST(MemoryImage, WatertightRecordsHoldTheVerticesAndTheUnitNormal) {
  Scene scene = test::tiny_scene();
  scene.positions[5] = scene.positions[1];  // triangle 3 = (0, 5, 1) has zero area
  const MemoryImage image = build_memory_image(scene, test::single_leaf_tree(4), IsectMode::kWatertight);
  const ImageLayout l = validate_memory_image(image.bytes, "w.rpu");
  EXPECT_EQ(l.isect_mode, IsectMode::kWatertight);
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const std::size_t at = l.isect_records.offset + i * mm::kTriangleRecordWatertightBytes;
    const glm::vec4 a = load_float4(image.bytes, at + mm::kTriangleRecordRow0At);
    const glm::vec4 b = load_float4(image.bytes, at + mm::kTriangleRecordRow1At);
    const glm::vec4 c = load_float4(image.bytes, at + mm::kTriangleRecordRow2At);
    EXPECT_EQ(glm::vec3(a), scene.positions[scene.triangles[i].x]);
    EXPECT_EQ(glm::vec3(b), scene.positions[scene.triangles[i].y]);
    EXPECT_EQ(glm::vec3(c), scene.positions[scene.triangles[i].z]);
    const glm::dvec3 n(a.w, b.w, c.w);
    if (i == 3) {
      EXPECT_EQ(n, glm::dvec3(0.0)) << "a zero-area triangle has no normal";
      continue;
    }
    EXPECT_NEAR(glm::length(n), 1.0, 1e-7) << "triangle " << i;
    EXPECT_NEAR(glm::dot(n, glm::dvec3(b - a)), 0.0, 1e-6) << "triangle " << i;
    EXPECT_NEAR(glm::dot(n, glm::dvec3(c - a)), 0.0, 1e-6) << "triangle " << i;
    EXPECT_GT(glm::dot(n, glm::cross(glm::dvec3(b - a), glm::dvec3(c - a))), 0.0) << "triangle " << i;
  }
}

// The scene record holds where one ulp of the tree's format sits in an fp32 pattern.
TEST(MemoryImage, RayOffsetShiftIsTheFormatsUlp) {
  const Scene scene = test::tiny_scene();
  KdTree tree = test::single_leaf_tree(4);
  for (const auto& [format, shift] : {std::pair{fp::Format{7, 16}, 7u}, {fp::Format{8, 7}, 16u},
                                       {fp::Format{5, 10}, 13u}, {fp::Format{5, 1}, 22u}}) {
    tree.format = format;
    const ImageLayout l = validate_memory_image(build_memory_image(scene, tree, IsectMode::kWoop).bytes, "f.rpu");
    EXPECT_EQ(l.ray_offset_shift, shift) << "E" << format.exponent_bits << "M" << format.fraction_bits;
  }
}

// The records hold the triangles in the tree's kd space (world x 2^-s, exactly), the
// scene record holds s; the vertex positions shaders read stay in world space.
TEST(MemoryImage, RecordsAreInTheTreesKdSpace) {
  const Scene scene = test::tiny_scene();
  KdTree tree = test::single_leaf_tree(4);
  tree.scale_exponent = 3;
  const MemoryImage image = build_memory_image(scene, tree, IsectMode::kWatertight);
  const ImageLayout l = validate_memory_image(image.bytes, "kd.rpu");
  EXPECT_EQ(l.kd_scale_exponent, 3);
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const std::size_t at = l.isect_records.offset + i * mm::kTriangleRecordWatertightBytes;
    EXPECT_EQ(glm::vec3(load_float4(image.bytes, at + mm::kTriangleRecordRow0At)),
              scene.positions[scene.triangles[i].x] / 8.0f);
  }
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    EXPECT_EQ(glm::vec3(load_float4(image.bytes, l.vertex_positions.offset + 16 * i)), scene.positions[i]);
  }
}

TEST(MemoryImage, SceneWithoutNormalsOrUvsHasEmptySections) {
  Scene scene = test::tiny_scene();
  scene.normals.clear();
  scene.uvs.clear();
  const ImageLayout l = validate_memory_image(
      build_memory_image(scene, test::single_leaf_tree(4), IsectMode::kWoop).bytes, "n.rpu");
  EXPECT_EQ(l.vertex_normals.count, 0u);
  EXPECT_EQ(l.vertex_uvs.bytes, 0u);
}

TEST(MemoryImage, DegenerateTriangleHasNoWoopTransformAndIsNamed) {
  Scene scene = test::tiny_scene();
  scene.positions[5] = scene.positions[1];  // triangle 3 = (0, 5, 1) has zero area
  try {
    build_memory_image(scene, test::single_leaf_tree(4), IsectMode::kWoop);
    FAIL() << "accepted a degenerate triangle";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tiny: triangle 3 "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
  // The watertight test needs no transform.
  EXPECT_NO_THROW(build_memory_image(scene, test::single_leaf_tree(4), IsectMode::kWatertight));
}

TEST(MemoryImage, TreeThatDoesNotFitTheSceneIsRejectedAtBuild) {
  KdTree tree = test::split_tree();
  tree.prim_refs[2] = 4;
  EXPECT_THROW(build_memory_image(test::tiny_scene(), tree, IsectMode::kWoop), Error);
}

TEST(MemoryImage, ParameterTooLargeForFp32IsAnError) {
  Scene scene = test::tiny_scene();
  scene.materials[1].shininess = 1e300;
  try {
    build_memory_image(scene, test::split_tree(), IsectMode::kWoop);
    FAIL() << "accepted 1e300";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("material 1 (\"mirror\") shininess"), std::string::npos) << e.what();
  }
}

TEST(MemoryImage, FileErrorsNameTheFile) {
  const fs::path missing = fs::path(::testing::TempDir()) / "no-such-dir" / "x.rpu";
  try {
    load_memory_image(missing);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  try {
    save_memory_image(MemoryImage{{1, 2, 3}}, missing);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

// --- One broken rule per test ------------------------------------------------------

using BadImage = Fixture;

TEST_F(BadImage, TruncatedAtSeveralCutPoints) {
  for (const std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{15}, std::size_t{16}, entry(4),
                                std::size_t{layout.kd_nodes.offset + 5}, bytes.size() - 1}) {
    const std::span<const std::uint8_t> part(bytes.data(), cut);
    expect_rejected(part, {"bad.rpu: header: ", "(truncated)"});
  }
}

TEST_F(BadImage, TrailingBytes) {
  bytes.push_back(0);
  expect_rejected(bytes, {"bad.rpu: header: total_bytes at offset 0x8: ", "(trailing bytes)"});
}

TEST_F(BadImage, WrongMagic) {
  out()[0] = 'X';
  expect_rejected(bytes, {"bad.rpu: header: magic at offset 0x0: ", "not an rpu memory image"});
}

TEST_F(BadImage, WrongVersion) {
  store_u32(out(), mm::kHeaderVersionAt, mm::kImageVersion + 1);
  expect_rejected(bytes, {"bad.rpu: header: version at offset 0x4: ", fmt::format("version {}", mm::kImageVersion + 1)});
}

TEST_F(BadImage, SectionTablePastTheEnd) {
  store_u32(out(), mm::kHeaderSectionCountAt, 0x10000000u);
  expect_rejected(bytes, {"bad.rpu: header: section_count at offset 0xc: ", "past the end of the image"});
}

TEST_F(BadImage, SectionOutOfBounds) {
  const std::size_t e = entry_of(mm::kSectionIdCamera);
  const std::uint32_t past = (layout.total_bytes + 63u) / 64u * 64u;
  store_u32(out(), e + mm::kSectionEntryOffsetAt, past);
  expect_rejected(bytes, {fmt::format("bad.rpu: camera: section at offset {:#x}: ", past), "run past the end"});
}

TEST_F(BadImage, Misaligned) {
  const std::size_t e = entry_of(mm::kSectionIdPrimRefs);
  store_u32(out(), e + mm::kSectionEntryOffsetAt, layout.prim_refs.offset + 4);
  expect_rejected(bytes, {fmt::format("bad.rpu: prim_refs: section at offset {:#x}: ", layout.prim_refs.offset + 4),
                  "not aligned to 64 bytes"});
}

TEST_F(BadImage, SectionInsideTheHeader) {
  store_u32(out(), entry_of(mm::kSectionIdLights) + mm::kSectionEntryOffsetAt, 0);
  expect_rejected(bytes, {"bad.rpu: lights: section at offset 0x0: ", "inside the header"});
}

TEST_F(BadImage, Overlapping) {
  store_u32(out(), entry_of(mm::kSectionIdPrimRefs) + mm::kSectionEntryOffsetAt, layout.kd_nodes.offset);
  expect_rejected(bytes, {fmt::format("section at offset {:#x}: overlaps ", layout.kd_nodes.offset)});
}

TEST_F(BadImage, CountBytesMismatch) {
  store_u32(out(), entry_of(mm::kSectionIdTriangles) + mm::kSectionEntryCountAt, layout.triangles.count + 1);
  expect_rejected(bytes, {fmt::format("bad.rpu: triangles: section at offset {:#x}: ", layout.triangles.offset),
                  "64 bytes is not 5 records of 16 bytes"});
}

TEST_F(BadImage, MissingSection) {
  // Drop the last table entry (the camera): the table shrinks by one.
  store_u32(out(), mm::kHeaderSectionCountAt, 9);
  expect_rejected(bytes, {"bad.rpu: camera: section table at offset 0x10: the section is missing"});
}

TEST_F(BadImage, DuplicateSection) {
  store_u32(out(), entry(9) + mm::kSectionEntryIdAt, mm::kSectionIdScene);
  expect_rejected(bytes, {fmt::format("bad.rpu: section_table: entry 9 at offset {:#x}: a second scene section", entry(9))});
}

TEST_F(BadImage, UnknownSectionId) {
  store_u32(out(), entry(3) + mm::kSectionEntryIdAt, 99);
  expect_rejected(bytes, {"section_table: entry 3", "unknown section id 99"});
}

TEST_F(BadImage, SceneCountsDisagreeWithSections) {
  store_u32(out(), layout.scene.offset + mm::kSceneRecordLightCountAt, 2);
  expect_rejected(bytes, {"bad.rpu: lights: section at offset", "3 records, but the scene record", "says 2 lights"});
}

TEST_F(BadImage, ChildIndexOutOfRange) {
  store_u32(out(), node(0), KdNode::inner(0, 9999, 0.5f).word0);
  expect_rejected(bytes, {fmt::format("bad.rpu: kd_nodes: node 0 at offset {:#x}: above child 9999 out of range (5 nodes)",
                                     node(0))});
}

TEST_F(BadImage, ChildIndexPointingBackwards) {
  store_u32(out(), node(2), KdNode::inner(1, 1, 0.25f).word0);
  expect_rejected(bytes, {fmt::format("bad.rpu: kd_nodes: node 2 at offset {:#x}: above child 1 does not come after "
                                     "the node (a cycle)", node(2))});
  store_u32(out(), node(2), KdNode::inner(1, 2, 0.25f).word0);  // itself
  expect_rejected(bytes, {"node 2", "above child 2 does not come after the node (a cycle)"});
}

TEST_F(BadImage, BelowChildOutOfRange) {
  store_u32(out(), node(4), KdNode::inner(2, 4, 1.0f).word0);
  expect_rejected(bytes, {"node 4", "above child 4 does not come after"});
  // The last node as an inner node has no below child either, whatever its above child.
  store_u32(out(), node(4), KdNode::inner(2, 5, 1.0f).word0);
  expect_rejected(bytes, {"node 4", "above child 5 out of range (5 nodes)"});
}

TEST_F(BadImage, LeafCountPastTheList) {
  store_u32(out(), node(3), KdNode::leaf(3, 4).word0);
  expect_rejected(bytes, {fmt::format("bad.rpu: kd_nodes: node 3 at offset {:#x}: leaf primitives [4, 7) run past the "
                                     "primitive list (6 entries)", node(3))});
}

TEST_F(BadImage, LeafFirstIndexHugeDoesNotWrap) {
  store_u32(out(), node(4) + mm::kKdNodeWord1At, 0xffffffffu);
  store_u32(out(), node(4), KdNode::leaf(2, 0).word0);
  expect_rejected(bytes, {"node 4", "[4294967295, 4294967297) run past"});
}

TEST_F(BadImage, PrimRefPastTriangleCount) {
  store_u32(out(), layout.prim_refs.offset + 3 * 4, 4);
  expect_rejected(bytes, {fmt::format("bad.rpu: prim_refs: entry 3 at offset {:#x}: triangle 4 out of range (4 "
                                     "triangles)", layout.prim_refs.offset + 12)});
}

TEST_F(BadImage, NaNSplit) {
  store_f32(out(), node(2) + mm::kKdNodeWord1At, std::numeric_limits<float>::quiet_NaN());
  expect_rejected(bytes, {fmt::format("bad.rpu: kd_nodes: node 2 at offset {:#x}: the split value is NaN", node(2))});
}

TEST_F(BadImage, NaNBounds) {
  store_f32(out(), layout.scene.offset + mm::kSceneRecordBoundsHiAt + 4, std::numeric_limits<float>::quiet_NaN());
  expect_rejected(bytes, {"bad.rpu: scene: bounds_hi at offset", "component 1 is nan"});
}

TEST_F(BadImage, KdScaleExponentOutOfRange) {
  store_u32(out(), layout.scene.offset + mm::kSceneRecordKdScaleExponentAt, static_cast<std::uint32_t>(-127));
  expect_rejected(bytes, {fmt::format("bad.rpu: scene: kd_scale_exponent at offset {:#x}: -127 is outside "
                                      "[-126, 127]",
                                      layout.scene.offset + mm::kSceneRecordKdScaleExponentAt)});
}

TEST_F(BadImage, RayOffsetShiftBeyondAnyFormat) {
  store_u32(out(), layout.scene.offset + mm::kSceneRecordRayOffsetShiftAt, 23);
  expect_rejected(bytes, {fmt::format("bad.rpu: scene: ray_offset_shift at offset {:#x}: 23 is outside [0, 22]",
                                      layout.scene.offset + mm::kSceneRecordRayOffsetShiftAt)});
}

TEST_F(BadImage, UnknownIsectMode) {
  store_u32(out(), layout.scene.offset + mm::kSceneRecordIsectModeAt, 7);
  expect_rejected(bytes, {fmt::format("bad.rpu: scene: isect_mode at offset {:#x}: unknown intersection mode 7",
                                     layout.scene.offset + mm::kSceneRecordIsectModeAt)});
}

TEST_F(BadImage, TriangleVertexOutOfRange) {
  store_u32(out(), layout.triangles.offset + mm::kTriangleBytes + mm::kTriangleCAt, 6);
  expect_rejected(bytes, {"bad.rpu: triangles: triangle 1 at offset", "vertex 6 out of range (6 vertices)"});
}

TEST_F(BadImage, TriangleMaterialOutOfRange) {
  store_u32(out(), layout.triangles.offset + mm::kTriangleMaterialAt, 3);
  expect_rejected(bytes, {"bad.rpu: triangles: triangle 0 at offset", "material 3 out of range (3 materials)"});
}

TEST_F(BadImage, IsectRecordNotFinite) {
  store_f32(out(), layout.isect_records.offset + mm::kTriangleRecordWoopBytes + 20, std::numeric_limits<float>::infinity());
  expect_rejected(bytes, {"bad.rpu: isect_records: record 1 at offset", "a component is inf"});
}

TEST_F(BadImage, UnknownLightKind) {
  store_u32(out(), layout.lights.offset + 2 * mm::kLightBytes + mm::kLightKindAt, 3);
  expect_rejected(bytes, {"bad.rpu: lights: light 2 at offset", "unknown light kind 3"});
}

}  // namespace
}  // namespace rpu
