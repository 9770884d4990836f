// Mesh files that lie about their size or end early: each is an rpu::Error naming the
// file and what it promised, raised before Assimp allocates what the header declares; a
// file without triangles is a warning that leaves the scene's other meshes alone
// (docs/scene-format.md, "Bad mesh files"). Each test writes its files into a fresh
// temp directory.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <assimp/material.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "common/error.hpp"
#include "scene/mesh.hpp"
#include "scene/resolve.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

class MeshFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("rpu_mesh_") + info->name() + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }
  // The message of the rpu::Error that loading `name` throws.
  std::string error_of(const std::string& name) const {
    try {
      load_mesh(dir_ / name, MeshOptions{});
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }

  fs::path dir_;
};

template <typename T>
std::string bytes_of(T value) {
  std::string out(sizeof value, '\0');
  std::memcpy(out.data(), &value, sizeof value);
  return out;
}
std::string floats(std::initializer_list<float> values) {
  std::string out;
  for (const float v : values) out += bytes_of(v);
  return out;
}

// A binary PLY header for `vertices` float positions and `faces` int index lists.
std::string binary_ply(int vertices, int faces) {
  return fmt::format(
      "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n"
      "property float y\nproperty float z\nelement face {}\n"
      "property list uchar int vertex_indices\nend_header\n",
      vertices, faces);
}

TEST_F(MeshFile, OffHeaderPromisingAGigavertexIsRefusedBeforeAllocating) {
  // 40 bytes that promise 10^9 vertices: Assimp would allocate 12 GB for them.
  const std::string off = "OFF\n1000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n\n\n\n";
  ASSERT_EQ(off.size(), 40u);
  const std::string path = write("huge.off", off);
  EXPECT_EQ(error_of("huge.off"),
            path + ": the header promises 1000000000 vertices, but the 21 bytes after the header "
                   "can hold at most 3 (each takes at least 6 bytes): the file is truncated or its "
                   "header is wrong");
}

TEST_F(MeshFile, OffWithMoreFacesDeclaredThanLinesIsRefused) {
  const std::string path = write("faces.off", "OFF\n3 5 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of("faces.off"),
            path + ": the header promises 5 faces, but the 8 bytes left after the vertex lines "
                   "can hold at most 2 (each takes at least 4 bytes): the file is truncated or its "
                   "header is wrong");
}

TEST_F(MeshFile, FaceWithoutIndicesIsAnErrorNotAnAssimpAssert) {
  // Room for two faces by size (a long vertex line), but one face line: Assimp leaves the
  // second face empty and Triangulate asserts on it.
  const std::string path =
      write("empty.off", "OFF\n3 2 0\n0 0 0                          \n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of("empty.off"), path + ": face 1 has no vertices (the file holds fewer faces "
                                          "than it declares, or a face line is empty)");
}

TEST_F(MeshFile, BinaryPlyPromisingMoreThanItHoldsIsRefused) {
  // Eight vertices and four faces promised; three vertices and one face present. Assimp
  // reads on into its buffer's padding and post-processing crashes on the indices.
  const std::string path = write("short.ply", binary_ply(8, 4) + floats({0, 0, 0, 1, 0, 0, 0, 1, 0}) +
                                                  bytes_of<std::uint8_t>(3) + bytes_of(0) +
                                                  bytes_of(1) + bytes_of(2));
  EXPECT_EQ(error_of("short.ply"),
            path + ": the header promises 8 vertices, but the 49 bytes after the header can hold "
                   "at most 4 (each takes at least 12 bytes): the file is truncated or its header "
                   "is wrong");
  const std::string giga = write("giga.ply", binary_ply(1000000000, 1) + floats({0, 0, 0}));
  EXPECT_EQ(error_of("giga.ply").rfind(giga + ": the header promises 1000000000 vertices", 0), 0u)
      << error_of("giga.ply");
}

TEST_F(MeshFile, BinaryPlyEndingInsideItsLastFaceIsRefused) {
  // The counts fit the size, but the last face's indices are cut off.
  const std::string header = binary_ply(3, 2);
  const std::string path = write("cut.ply", header + floats({0, 0, 0, 1, 0, 0, 0, 1, 0}) +
                                                bytes_of<std::uint8_t>(3) + bytes_of(0) + bytes_of(1) +
                                                bytes_of(2) + bytes_of<std::uint8_t>(3) + bytes_of(0));
  EXPECT_EQ(error_of("cut.ply"), path + ": face 1 of 2 (offset " + std::to_string(header.size() + 50) +
                                      ") has a list of 3 items, but only 4 bytes follow: the file is "
                                      "truncated or corrupt");
}

TEST_F(MeshFile, BinaryPlyListLongerThanTheFileIsRefused) {
  // A list length of 4 * 10^9 items: Assimp resizes the list to it before reading one.
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  const std::string path = write("list.ply", header + std::string(36, '\0') + std::string("\xee\x6b\x28\x00", 4) +
                                                 std::string(12, '\0'));
  EXPECT_EQ(error_of("list.ply"), path + ": face 0 of 1 (offset " + std::to_string(header.size() + 40) +
                                      ") has a list of 4000000000 items, but only 12 bytes follow: "
                                      "the file is truncated or corrupt");
}

TEST_F(MeshFile, AsciiPlyListLongerThanItsLineIsRefused) {
  const std::string path = write(
      "list.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "4000000000 0 1 2\n");
  EXPECT_EQ(error_of("list.ply"),
            path + ": line 13: face 0 of 1 has a list of 4000000000 items, more than its line's 16 "
                   "characters");
  const std::string short_list = write(
      "short.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "4 0 1 2\n");
  EXPECT_EQ(error_of("short.ply"),
            short_list + ": line 13: face 0 of 1 has a list of 4 items, but the line holds only 3");
}

TEST_F(MeshFile, AsciiPlyEndingEarlyIsRefused) {
  // Two faces declared and room for them by size, but one face line.
  const std::string path = write(
      "early.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "3 0 1 2                  \n");
  EXPECT_EQ(error_of("early.ply"), path + ": the file ends before face 1 of 2 (line 14): it is "
                                          "truncated or its header promises too much");
}

TEST_F(MeshFile, AsciiPlyLineShorterThanItsPropertiesIsRefused) {
  // Assimp would read the missing value from the tail of an earlier, longer line.
  const std::string path = write(
      "short.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0\n0 1 0 0 0 0\n"
      "3 0 1 2\n");
  EXPECT_EQ(error_of("short.ply"), path + ": line 11: vertex 1 of 3 has fewer values than its 3 properties");
}

TEST_F(MeshFile, PlyMaterialAndEdgeElementsAreCapped) {
  // Assimp makes a whole aiMaterial of each material instance: 5 MB of one-byte materials
  // took 23 GB. rpu uses neither materials nor edges from a PLY file.
  const std::string triangle =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n";
  const std::string materials =
      write("materials.ply", triangle + "element material 300\nproperty uchar ambient_red\nend_header\n" +
                                 std::string(36 + 13 + 300, '\0'));
  EXPECT_EQ(error_of("materials.ply"),
            materials + ": the header declares 300 materials; Assimp makes a whole material of each, "
                        "and rpu reads at most 256 (rpu takes materials from the scene file)");
  const std::string edges = write("edges.ply", triangle + "element edge 600000\nproperty uchar a\n"
                                                          "property uchar b\nend_header\n" +
                                                   std::string(36 + 13 + 1200000, '\0'));
  EXPECT_EQ(error_of("edges.ply"),
            edges + ": the header declares 1200000 edge and material values; Assimp keeps each at "
                    "about 100 bytes, and rpu reads at most 1048576 (rpu does not use them)");
}

TEST_F(MeshFile, PlyEmptyMaterialElementIsRefusedBeforeAssimpLeaks) {
  // Found by fuzz_mesh_files: Assimp 5.2 leaks on a material element of no instances.
  const std::string path =
      write("no_materials.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nelement material 0\n"
            "property uchar ambient_red\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of("no_materials.ply"),
            path + ": the \"material\" element has no instances; leave it out (Assimp 5.2 mishandles an empty "
                   "material element, and rpu takes materials from the scene file)");
}

// Found by fuzz_mesh_files: a number longer than an int in a line statement made the
// OBJ check step past the statement's end (a heap overflow under ASan).
TEST_F(MeshFile, ObjNumberLongerThanAnIntIsReadWithinTheLine) {
  const fs::path corpus =
      fs::path(RPU_SOURCE_DIR) / "tests/fuzz/corpus/mesh_files/regress_obj_line_number_past_the_end.obj";
  try {
    load_mesh(corpus, MeshOptions{});
    ADD_FAILURE() << "the file's bad face index was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read the mesh: OBJ: Invalid face index"), std::string::npos)
        << e.what();
  }
}

// Assimp triangulates in time quadratic in a polygon's corners (65,536 took 33 s): the
// corners squared, summed over a file's polygons, are capped at 2^30.
TEST_F(MeshFile, PolygonsTooLargeToTriangulateInTimeAreRefused) {
  const auto polygon_obj = [](int corners, int polygons) {
    std::string text;
    for (int i = 0; i < corners; ++i) text += fmt::format("v {} {} 0\n", i, i % 2);
    for (int p = 0; p < polygons; ++p) {
      text += "f";
      for (int i = 1; i <= corners; ++i) text += fmt::format(" {}", i);
      text += "\n";
    }
    return text;
  };
  const std::string one = write("one.obj", polygon_obj(33000, 1));
  EXPECT_EQ(error_of("one.obj"),
            one + ": line 33001: the polygons up to here (the largest of 33000 corners) would take Assimp's "
                  "triangulation more than 1073741824 steps (corners squared, summed); split them into smaller "
                  "polygons or triangles");
  // Their sum counts: two of 24,000 corners are refused at the second.
  const std::string two = write("two.obj", polygon_obj(24000, 2));
  EXPECT_NE(error_of("two.obj").find(two + ": line 24002: the polygons up to here (the largest of 24000"),
            std::string::npos)
      << error_of("two.obj");
  // PLY face lists count the same way.
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 33000\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
  ply += std::string(33000 * 12, '\0');
  const std::int32_t corners = 33000;
  ply.append(reinterpret_cast<const char*>(&corners), 4);
  for (std::int32_t i = 0; i < corners; ++i) ply.append(reinterpret_cast<const char*>(&i), 4);
  const std::string path = write("one.ply", ply);
  EXPECT_NE(error_of("one.ply").find(path + ": face 0 of 1: the polygons up to here (the largest of 33000"),
            std::string::npos)
      << error_of("one.ply");
}

TEST_F(MeshFile, AsciiPlyListItemThatIsNotANumberIsRefused) {
  // Assimp's cursor stays on it, so every item of the list reads it again: a list length
  // of 10^9 on a short line spun for minutes (found by fuzz_mesh_files).
  const std::string path = write(
      "item.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "3 0 x 2\n");
  EXPECT_EQ(error_of("item.ply"), path + ": line 13: face 0 of 1 has \"x\" in its list, which is not a number");
}

TEST_F(MeshFile, PlyFaceIndexPastTheLastVertexIsAnError) {
  const std::string path = write(
      "index.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "3 0 1 7\n");
  EXPECT_EQ(error_of("index.ply"), path + ": face 0 names vertex 7, but there are 3 vertices");
}

TEST_F(MeshFile, BinaryStlWithAHugeTriangleCountIsRefused) {
  const std::string path = write("huge.stl", std::string(80, ' ') + bytes_of(std::uint32_t{1000000000}) +
                                                 std::string(50, '\0'));
  EXPECT_EQ(error_of("huge.stl"),
            path + ": the binary STL header promises 1000000000 triangles (84 + 50 x 1000000000 = "
                   "50000000084 bytes), but the file has 134 bytes: it is truncated or its header is "
                   "wrong");
  // The same file with its count right reads.
  write("one.stl", std::string(80, ' ') + bytes_of(std::uint32_t{1}) + floats({0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}) +
                       std::string(2, '\0'));
  EXPECT_EQ(load_mesh(dir_ / "one.stl", MeshOptions{}).triangles.size(), 1u);
}

TEST_F(MeshFile, OffFaceOfNoCornersIsRefused) {
  // Assimp skips such a face line and takes one off the face count; enough of them wrap
  // the count around and crash it (found by fuzz_mesh_files).
  const std::string path = write("corners.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\nabc\n");
  EXPECT_EQ(error_of("corners.off"),
            path + ": line 7: face 1 has 0 corners; Assimp 5.2 reads OFF faces of 1 to 9");
}

TEST_F(MeshFile, AsciiStlWithANonNumberIsRefusedBeforeAssimpLeaks) {
  // Assimp's ascii STL reader throws on it and leaks its meshes (found by fuzz_mesh_files).
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 x\n"
      "endloop\nendfacet\nendsolid t\n";
  const std::string path = write("nan.stl", stl);
  EXPECT_EQ(error_of("nan.stl"), path + ": offset " + std::to_string(stl.rfind('x')) +
                                     ": vertex \"x\" is not a number");
}

TEST_F(MeshFile, ObjLineOfOneVertexIsRefusedBeforeAssimpLeaks) {
  // Assimp counts it as no segment but copies its vertex, throws, and leaks the meshes it
  // has built (found by fuzz_mesh_files).
  const std::string path = write("line.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 2\n");
  EXPECT_EQ(error_of("line.obj"), path + ": line 5: a line statement with one vertex (Assimp 5.2 "
                                         "fails on it and leaks what it has read; give two or more)");
}

TEST_F(MeshFile, PointsAndLinesOnlyMeshIsAWarningAndTheSceneKeepsItsOtherMeshes) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string points = write("points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n");
  const std::string lines = write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  const std::string cloud = write("cloud.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n");
  write("x.json", R"({"meshes": [{"file": "points.obj"}, {"file": "tri.obj"}, {"file": "lines.obj"},
                                 {"file": "cloud.ply"}]})");
  const Scene s = resolve_scene((dir_ / "x.json").string());
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 3u);
  EXPECT_EQ(s.warnings[0], points + ": no triangles in the file");
  EXPECT_EQ(s.warnings[1], lines + ": no triangles in the file");
  EXPECT_EQ(s.warnings[2], cloud + ": no triangles in the file");
}

TEST_F(MeshFile, AssimpAssertionIsAnErrorNotAnAbort) {
  // Debian's libassimp checks its ai_asserts; AddBinaryProperty asserts a non-zero size.
  // The library's call must reach rpu's handler (mesh.cpp), which throws.
  aiMaterial material;
  const int value = 0;
  EXPECT_THROW(material.AddBinaryProperty(&value, 0, "key", 0, 0, aiPTI_Integer), Error);
}

}  // namespace
}  // namespace rpu
