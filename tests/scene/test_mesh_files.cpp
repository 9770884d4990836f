// Mesh files whose faces Assimp's post-processing cannot take: each is an rpu::Error
// naming the file and the face; a file without triangles is a warning that leaves the
// scene's other meshes alone (docs/scene-format.md, "Bad mesh files"). Each test writes
// its files into a fresh temp directory.
#include <filesystem>
#include <fstream>
#include <string>

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

TEST_F(MeshFile, FaceWithoutIndicesIsAnErrorNotAnAssimpAssert) {
  // Room for two faces by size (a long vertex line), but one face line: Assimp leaves the
  // second face empty and Triangulate asserts on it.
  const std::string path =
      write("empty.off", "OFF\n3 2 0\n0 0 0                          \n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of("empty.off"), path + ": face 1 has no vertices (the file holds fewer faces "
                                          "than it declares, or a face line is empty)");
}

TEST_F(MeshFile, PlyFaceIndexPastTheLastVertexIsAnError) {
  const std::string path = write(
      "index.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "3 0 1 7\n");
  EXPECT_EQ(error_of("index.ply"), path + ": face 0 names vertex 7, but there are 3 vertices");
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

}  // namespace
}  // namespace rpu
