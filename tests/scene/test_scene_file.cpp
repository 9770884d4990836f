// Scene files and bare meshes: every kind of bad input is an rpu::Error whose message
// names the file and the line:column or JSON pointer; degenerate triangles are a
// counted warning. Each test writes its own small files into a fresh temp directory.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/error.hpp"
#include "scene/geometry.hpp"
#include "scene/mesh.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"
#include "scene/scene_file.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

class SceneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("rpu_scene_") + info->test_suite_name() + "_" + info->name() + "_" +
            std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }
  // The message of the rpu::Error that loading `name` throws.
  std::string error_of(const std::string& name) const {
    try {
      resolve_scene((dir_ / name).string());
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// A scene around the one-triangle mesh, with `extra` top-level keys.
std::string scene_with(const std::string& extra) {
  return R"({"meshes": [{"file": "tri.obj"}])" + (extra.empty() ? "" : ", " + extra) + "}";
}

TEST_F(SceneFile, MalformedJsonReportsLineAndColumn) {
  write("x.json", "{\n  \"camera\": ,\n}\n");
  EXPECT_EQ(error_of("x.json").rfind(file("x.json") + ":2:13: malformed JSON: ", 0), 0u)
      << error_of("x.json");
}

TEST_F(SceneFile, TruncatedJsonReportsTheEnd) {
  write("x.json", "{\"meshes\": [\n");
  EXPECT_NE(error_of("x.json").find(file("x.json") + ":2:1: malformed JSON"), std::string::npos)
      << error_of("x.json");
}

TEST_F(SceneFile, NumberBeyondDoubleIsMalformedJson) {
  write("x.json", scene_with(R"("background": [2e308, 0, 0])"));
  EXPECT_EQ(error_of("x.json"), file("x.json") + ": malformed JSON: number overflow parsing '2e308'");
}

TEST_F(SceneFile, UnknownKeyNamesItsPointer) {
  write("tri.obj", kTriangleObj);
  write("x.json", scene_with(R"("camra": {})"));
  EXPECT_EQ(error_of("x.json"),
            file("x.json") + ": /camra: unknown key \"camra\" (expected one of: comment, camera, "
                             "background, lights, materials, meshes, procedural)");
  write("y.json", R"({"meshes": [{"file": "tri.obj", "transform": {"rotat": {}}}]})");
  EXPECT_NE(error_of("y.json").find(": /meshes/0/transform/rotat: unknown key"), std::string::npos);
}

TEST_F(SceneFile, WrongTypeNamesPointerAndExpectation) {
  write("tri.obj", kTriangleObj);
  write("x.json", scene_with(R"("materials": [{"name": "a"}, {"name": "b"},
                                              {"name": "c", "diffuse": [1, 2]}])"));
  EXPECT_EQ(error_of("x.json"),
            file("x.json") + ": /materials/2/diffuse: expected an array of 3 numbers, got an array of 2");
  write("y.json", scene_with(R"("background": "blue")"));
  EXPECT_EQ(error_of("y.json"), file("y.json") +
                                    ": /background: expected an array of 3 numbers, got the "
                                    "string \"blue\"");
  write("z.json", R"({"meshes": [{"file": "tri.obj", "smooth": 1}]})");
  EXPECT_EQ(error_of("z.json"),
            file("z.json") + ": /meshes/0/smooth: expected true or false, got the number 1");
}

TEST_F(SceneFile, UnknownMaterialIsAnError) {
  write("tri.obj", kTriangleObj);
  write("x.json", R"({"materials": [{"name": "red"}],
                     "meshes": [{"file": "tri.obj", "material": "blue"}]})");
  EXPECT_EQ(error_of("x.json"),
            file("x.json") + ": /meshes/0/material: unknown material \"blue\" (defined: red)");
}

TEST_F(SceneFile, DuplicateMaterialIsAnError) {
  write("tri.obj", kTriangleObj);
  write("x.json", scene_with(R"("materials": [{"name": "red"}, {"name": "red"}])"));
  EXPECT_EQ(error_of("x.json"), file("x.json") + ": /materials/1/name: duplicate material \"red\"");
}

TEST_F(SceneFile, MissingMeshFileIsAnError) {
  write("x.json", R"({"meshes": [{"file": "nowhere.obj"}]})");
  EXPECT_EQ(error_of("x.json"), file("x.json") + ": /meshes/0/file: mesh file " +
                                    file("nowhere.obj") + " not found");
}

TEST_F(SceneFile, UnsupportedFormatIncludesAssimpsMessage) {
  write("junk.xyz", "hello\n");
  write("x.json", R"({"meshes": [{"file": "junk.xyz"}]})");
  EXPECT_EQ(error_of("x.json"),
            file("x.json") + ": /meshes/0/file: " + file("junk.xyz") +
                ": cannot read the mesh: No suitable reader found for the file format of file \"" +
                file("junk.xyz") + "\".");
}

TEST_F(SceneFile, NonFiniteVertexNamesFileAndIndex) {
  write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  write("inf.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 1e39\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of("nan.obj"), file("nan.obj") + ": vertex 2 is not finite (nan, 1, 0)");
  EXPECT_EQ(error_of("inf.ply"), file("inf.ply") + ": vertex 1 is not finite (1, 0, inf)");
}

TEST_F(SceneFile, DegenerateTrianglesAreDroppedWithOneWarning) {
  // One good triangle; a repeated vertex, a collinear one and a needle.
  write("m.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 0.5 0.00000001 0\n"
        "f 1 2 3\nf 1 1 2\nf 1 2 4\nf 1 2 5\n");
  const Scene s = resolve_scene(file("m.obj"));
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            file("m.obj") + ": dropped 3 degenerate triangles (2 zero area, 1 needle or collinear)");
}

TEST_F(SceneFile, EmptySceneIsAnError) {
  write("x.json", R"({"materials": [{"name": "red"}]})");
  EXPECT_EQ(error_of("x.json"), file("x.json") +
                                    ": the scene has no triangles (give \"meshes\" or "
                                    "\"procedural\")");
  write("points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n");
  EXPECT_EQ(error_of("points.obj").rfind(file("points.obj"), 0), 0u) << error_of("points.obj");
}

TEST_F(SceneFile, OutOfRangeNumbersAreErrors) {
  write("tri.obj", kTriangleObj);
  write("fov0.json", scene_with(R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "vfov": 0})"));
  EXPECT_EQ(error_of("fov0.json"),
            file("fov0.json") + ": /camera/vfov: expected degrees in (0, 180), got 0");
  write("fovneg.json", scene_with(R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "vfov": -30})"));
  EXPECT_EQ(error_of("fovneg.json"),
            file("fovneg.json") + ": /camera/vfov: expected degrees in (0, 180), got -30");
  write("ior.json", scene_with(R"("materials": [{"name": "glass", "ior": -1.5}])"));
  EXPECT_EQ(error_of("ior.json"),
            file("ior.json") + ": /materials/0/ior: expected an index of refraction > 0, got -1.5");
  write("refl.json", scene_with(R"("materials": [{"name": "m", "reflectance": 1.5}])"));
  EXPECT_EQ(error_of("refl.json"),
            file("refl.json") + ": /materials/0/reflectance: expected a number in [0, 1], got 1.5");
  write("rough.json", scene_with(R"("materials": [{"name": "m", "roughness": -0.1}])"));
  EXPECT_EQ(error_of("rough.json"),
            file("rough.json") + ": /materials/0/roughness: expected a number in [0, 1], got -0.1");
  write("up.json", scene_with(R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 0, 2]})"));
  EXPECT_EQ(error_of("up.json"),
            file("up.json") + ": /camera/up: up is parallel to the view direction");
  write("scale.json", R"({"meshes": [{"file": "tri.obj", "transform": {"scale": [1, 0, 1]}}]})");
  EXPECT_EQ(error_of("scale.json"),
            file("scale.json") + ": /meshes/0/transform/scale: expected non-zero scale factors");
}

TEST_F(SceneFile, BadLightsAreErrors) {
  write("tri.obj", kTriangleObj);
  write("type.json", scene_with(R"("lights": [{"type": "spot", "position": [0, 0, 0]}])"));
  EXPECT_EQ(error_of("type.json"),
            file("type.json") +
                ": /lights/0/type: expected \"point\", \"directional\" or \"area\", got \"spot\"");
  write("area.json", scene_with(R"("lights": [{"type": "area", "corner": [0, 0, 0],
                                              "edge_u": [1, 0, 0], "edge_v": [2, 0, 0]}])"));
  EXPECT_EQ(error_of("area.json"), file("area.json") +
                                       ": /lights/0/edge_v: edge_v is parallel to edge_u (the "
                                       "light has no area)");
  write("missing.json", scene_with(R"("lights": [{"type": "point"}])"));
  EXPECT_EQ(error_of("missing.json"), file("missing.json") + ": /lights/0: missing key \"position\"");
  write("key.json", scene_with(R"("lights": [{"type": "directional", "direction": [0, -1, 0],
                                             "position": [0, 1, 0]}])"));
  EXPECT_NE(error_of("key.json").find(": /lights/0/position: unknown key \"position\""),
            std::string::npos);
}

TEST_F(SceneFile, MissingCachedMeshSaysToRunFetchMeshes) {
  const char* old = std::getenv("RPU_MESH_DIR");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("RPU_MESH_DIR", (dir_ / "cache").string().c_str(), 1);
  EXPECT_EQ(mesh_cache_dir(), dir_ / "cache");
  write("x.json", R"({"meshes": [{"file": "@meshes/bunny.ply"}]})");
  const std::string message = error_of("x.json");
  if (old != nullptr) {
    ::setenv("RPU_MESH_DIR", saved.c_str(), 1);
  } else {
    ::unsetenv("RPU_MESH_DIR");
  }
  EXPECT_EQ(message, file("x.json") + ": /meshes/0/file: @meshes/bunny.ply is not in the mesh cache " +
                         (dir_ / "cache").string() +
                         " (run scripts/fetch-meshes to fetch the meshes; RPU_MESH_DIR chooses "
                         "another cache)");
}

TEST_F(SceneFile, TransformsPlaceTheMesh) {
  write("tri.obj", kTriangleObj);
  write("x.json", R"({"meshes": [
      {"file": "tri.obj", "transform": {"translate": [10, 0, 0], "rotate": {"axis": [0, 0, 1], "degrees": 90}, "scale": 2}},
      {"file": "tri.obj", "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 5], [0, 0, 0, 1]]}]})");
  const Scene s = resolve_scene(file("x.json"));
  ASSERT_EQ(s.triangles.size(), 2u);
  // Scale 2, then a quarter turn about z, then +10 in x: (1, 0, 0) -> (10, 2, 0).
  const Bounds first = [&] {
    Scene one = s;
    one.triangles.resize(1);
    return scene_bounds(one);
  }();
  EXPECT_NEAR(first.lo.x, 8.0, 1e-5);
  EXPECT_NEAR(first.hi.x, 10.0, 1e-5);
  EXPECT_NEAR(first.hi.y, 2.0, 1e-5);
  EXPECT_NEAR(scene_bounds(s).hi.z, 5.0, 1e-6);
  // Defaults when the file gives no camera and lights: framing camera, one point light.
  EXPECT_EQ(s.camera.vfov_degrees, 40.0);
  EXPECT_EQ(s.lights.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].name, "default");
}

TEST_F(SceneFile, MirroringTransformKeepsTheWindingOutward) {
  write("tri.obj", kTriangleObj);
  write("x.json", R"({"meshes": [{"file": "tri.obj", "smooth": true, "transform": {"scale": [-1, 1, 1]}}]})");
  const Scene s = resolve_scene(file("x.json"));
  ASSERT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.normals.size(), s.positions.size());
  const glm::uvec3 t = s.triangles[0];
  const glm::vec3 geometric =
      glm::cross(s.positions[t.y] - s.positions[t.x], s.positions[t.z] - s.positions[t.x]);
  EXPECT_GT(glm::dot(geometric, s.normals[t.x]), 0.0f);
}

TEST_F(SceneFile, ProceduralKeepsItsCameraAndLightsAndMaterialsCanBeRestyled) {
  write("x.json", R"({"procedural": {"generator": "tetra", "size": 2},
                      "materials": [{"name": "tetra", "diffuse": [0, 0, 1], "roughness": 0.25,
                                     "shader": "glossy"}]})");
  const Scene s = resolve_scene(file("x.json"));
  EXPECT_EQ(s.triangles.size(), 16u);
  EXPECT_EQ(s.camera.position, make_builtin_scene("tetra").camera.position);
  EXPECT_EQ(s.lights.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].diffuse, glm::dvec3(0.0, 0.0, 1.0));
  EXPECT_EQ(s.materials[0].roughness, 0.25);
  EXPECT_EQ(s.materials[0].shader, "glossy");
  write("bad.json", R"({"procedural": {"generator": "teapot"}})");
  EXPECT_EQ(error_of("bad.json"), file("bad.json") +
                                      ": /procedural/generator: unknown generator \"teapot\" "
                                      "(expected one of: cornell, balls, tetra, stadium, scattered)");
  write("size.json", R"({"procedural": {"generator": "balls", "size": 2.5}})");
  EXPECT_EQ(error_of("size.json"),
            file("size.json") + ": /procedural/size: expected a whole number, got the number 2.5");
}

TEST_F(SceneFile, BareMeshGetsCameraLightAndGreyMaterial) {
  write("tri.obj", kTriangleObj);
  const Scene s = resolve_scene(file("tri.obj"));
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.camera.look_at, glm::dvec3(0.5, 0.5, 0.0));
  EXPECT_EQ(s.camera.vfov_degrees, 40.0);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].kind, LightKind::kPoint);
  EXPECT_LT(glm::length(s.lights[0].position - s.camera.position),
            glm::length(s.camera.position - s.camera.look_at));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_GT(s.materials[0].ambient.x, 0.0);
}

}  // namespace
}  // namespace rpu

namespace rpu {
namespace {

// nlohmann keeps the last of two equal keys; the file is ambiguous, so it is an error
// naming the object and the key.
TEST_F(SceneFile, DuplicateKeysAreErrors) {
  write("tri.obj", kTriangleObj);
  write("top.json", R"({"meshes": [{"file": "tri.obj"}], "background": [0, 0, 0], "background": [1, 1, 1]})");
  EXPECT_EQ(error_of("top.json"),
            file("top.json") + ": /: duplicate key \"background\" (the keys of an object must be unique)");
  write("nested.json", R"({"materials": [{"name": "a"}, {"name": "b", "diffuse": [1, 0, 0], "diffuse": [0, 1, 0]}],
                          "meshes": [{"file": "tri.obj", "material": "b"}]})");
  EXPECT_EQ(error_of("nested.json"),
            file("nested.json") + ": /materials/1: duplicate key \"diffuse\" (the keys of an object must be unique)");
  // Equal keys in different objects are fine.
  write("fine.json", R"({"materials": [{"name": "a"}, {"name": "b"}], "meshes": [{"file": "tri.obj", "material": "b"}]})");
  EXPECT_EQ(error_of("fine.json"), "no error");
}

// Text after the document is an error; so is a NUL byte, where nlohmann would stop
// reading and accept what came before.
TEST_F(SceneFile, BytesAfterTheDocumentAreErrors) {
  write("tri.obj", kTriangleObj);
  write("second.json", scene_with("") + " {}");
  EXPECT_NE(error_of("second.json").find(file("second.json") + ":1:"), std::string::npos) << error_of("second.json");
  EXPECT_NE(error_of("second.json").find("expected end of input"), std::string::npos);
  const fs::path nul = dir_ / "nul.json";
  std::ofstream(nul, std::ios::binary) << scene_with("") << '\n' << std::string(3, '\0') << "garbage";
  EXPECT_EQ(error_of("nul.json"),
            file("nul.json") + ":2:1: malformed JSON: a NUL byte (byte " + std::to_string(scene_with("").size() + 1) +
                " of " + std::to_string(scene_with("").size() + 11) + "); a scene file is UTF-8 text");
}

// A size given is the size asked for: a negative one is refused, never the default.
TEST_F(SceneFile, NegativeGeneratorSizesAreErrors) {
  write("neg.json", R"({"procedural": {"generator": "tetra", "size": -3}})");
  EXPECT_EQ(error_of("neg.json"), file("neg.json") +
                                      ": /procedural/size: tetra:-3: size must be 1..10 (levels of recursion; "
                                      "4^size triangles)");
  for (const std::string name : {"cornell:-100", "balls:-1", "tetra:-2"}) {
    EXPECT_THROW(make_builtin_scene(name), Error) << name;
  }
  EXPECT_NO_THROW(make_builtin_scene("tetra"));
}

}  // namespace
}  // namespace rpu
