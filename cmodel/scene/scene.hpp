#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace rpu {

// A scene as every view of the chip sees it: one world-space triangle soup plus the
// camera, lights and materials. docs/scene-format.md describes the JSON form.
//
// Vertex data is fp32 because the memory image holds fp32 and the kd-tree is built
// over exactly these values; the reference renderer widens them to double, so all
// views intersect the same triangles. Camera, light and material parameters are
// double here and rounded where a view stores them.

struct Camera {
  glm::dvec3 position{0.0, 0.0, 5.0};
  glm::dvec3 look_at{0.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double vfov_degrees = 45.0;    // vertical field of view
  double aperture_radius = 0.0;  // thin lens; 0 = pinhole
  double focus_distance = 0.0;   // thin lens; 0 = distance to look_at
};

enum class LightKind { kPoint, kDirectional, kArea };

struct Light {
  LightKind kind = LightKind::kPoint;
  glm::dvec3 color{1.0, 1.0, 1.0};  // linear RGB intensity, no distance falloff
  glm::dvec3 position{0.0};         // point: position; area: one corner
  glm::dvec3 direction{0.0, -1.0, 0.0};  // directional: unit direction light travels
  glm::dvec3 edge_u{0.0}, edge_v{0.0};   // area: the rectangle is position + s*edge_u + t*edge_v
};

struct Material {
  std::string name;
  glm::dvec3 ambient{0.0};
  glm::dvec3 diffuse{0.8};
  glm::dvec3 specular{0.0};
  double shininess = 1.0;      // Phong exponent
  double reflectance = 0.0;    // weight of the mirror ray
  double transmittance = 0.0;  // weight of the refracted ray
  double ior = 1.0;            // index of refraction of the inside
  double roughness = 0.0;      // glossy lobe's spread about the mirror ray (glossy shader); 0 = mirror
  std::string shader = "whitted";  // the firmware hit shader that renders it
};

struct Scene {
  std::string source;  // file or built-in name it came from, for messages
  Camera camera;
  std::vector<Light> lights;
  std::vector<Material> materials;
  glm::dvec3 background{0.0};

  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // per vertex: empty, or one per position
  std::vector<glm::vec2> uvs;      // per vertex: empty, or one per position
  std::vector<glm::uvec3> triangles;       // indices into positions
  std::vector<std::uint32_t> material_ids;  // one per triangle, index into materials

  // Counted, non-fatal problems (dropped degenerate triangles, ...), printed by the CLI.
  std::vector<std::string> warnings;
};

}  // namespace rpu
