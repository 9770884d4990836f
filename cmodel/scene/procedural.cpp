#include "scene/procedural.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "common/random_vector.hpp"
#include "scene/geometry.hpp"

namespace rpu {
namespace {

constexpr double kPi = std::numbers::pi;

double radians(double degrees) { return degrees * kPi / 180.0; }

std::uint32_t add_material(Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}

// A material from an SPD `lib_output_color(color, ka, kd, ks, shine, ang, kt, ior)`
// call: NFF's Ks is the mirror weight, `shine` the highlight weight, and `ang` the
// angle (degrees) at which the Phong highlight falls to half, so the exponent n solves
// cos(ang)^n = 1/2 (SPD lib's NFF output does the same).
Material spd_material(std::string name, glm::dvec3 color, double ka, double kd, double ks,
                      double shine, double ang, double kt, double ior) {
  Material m;
  m.name = std::move(name);
  m.ambient = ka * color;
  m.diffuse = kd * color;
  m.specular = glm::dvec3(shine);
  m.shininess = ang > 0.0 ? std::log(0.5) / std::log(std::cos(radians(ang))) : 1.0;
  m.reflectance = ks;
  m.transmittance = kt;
  // SPD writes ior 0 for opaque surfaces, where it means "unused"; 1 says the same
  // without breaking the rule that an ior is positive.
  m.ior = ior > 0.0 ? ior : 1.0;
  return m;
}

// One triangle with its own three vertices carrying the face normal.
void add_flat_triangle(Scene& s, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c,
                       std::uint32_t material) {
  const glm::vec3 n(glm::normalize(glm::cross(b - a, c - a)));
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  for (const glm::dvec3& p : {a, b, c}) {
    s.positions.emplace_back(p);
    s.normals.push_back(n);
  }
  s.triangles.emplace_back(base, base + 1, base + 2);
  s.material_ids.push_back(material);
}

// A planar quad a-b-c-d as two flat triangles whose front side faces `facing`.
void add_quad(Scene& s, std::array<glm::dvec3, 4> q, std::uint32_t material,
              const glm::dvec3& facing) {
  if (glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), facing - q[0]) < 0.0) {
    std::swap(q[1], q[3]);
  }
  add_flat_triangle(s, q[0], q[1], q[2], material);
  add_flat_triangle(s, q[0], q[2], q[3], material);
}

// A UV sphere, poles on local z: `slices` columns, slices/2 rows, exact normals,
// slices*(slices-2) triangles wound counter-clockwise seen from outside.
void add_sphere(Scene& s, const glm::dvec3& center, double radius, int slices,
                std::uint32_t material) {
  const int rows = slices / 2;
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  auto add_vertex = [&](const glm::dvec3& unit) {
    s.positions.emplace_back(center + radius * unit);
    s.normals.emplace_back(unit);
  };
  add_vertex({0.0, 0.0, 1.0});
  for (int i = 1; i < rows; ++i) {
    const double theta = kPi * i / rows;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * kPi * j / slices;
      add_vertex({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                  std::cos(theta)});
    }
  }
  add_vertex({0.0, 0.0, -1.0});
  const std::uint32_t north = base;
  const std::uint32_t south = base + 1 + static_cast<std::uint32_t>((rows - 1) * slices);
  auto ring = [&](int i, int j) {
    return base + 1 + static_cast<std::uint32_t>(i * slices + (j % slices));
  };
  auto add_triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    s.triangles.emplace_back(a, b, c);
    s.material_ids.push_back(material);
  };
  for (int j = 0; j < slices; ++j) add_triangle(north, ring(0, j), ring(0, j + 1));
  for (int i = 0; i + 1 < rows - 1; ++i) {
    for (int j = 0; j < slices; ++j) {
      add_triangle(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      add_triangle(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  }
  for (int j = 0; j < slices; ++j) add_triangle(ring(rows - 2, j), south, ring(rows - 2, j + 1));
}

// At most 1024 slices: a million triangles per sphere, as many as tetra:10. Without a
// bound, "cornell:100000" asked for 10^10 triangles and ran out of time and memory
// (found while fuzzing scene files).
constexpr int kMaxSlices = 1024;

void check_slices(int slices, std::string_view scene) {
  if (slices < 4 || slices > kMaxSlices || slices % 2 != 0) {
    throw Error(fmt::format("{}: sphere tessellation {} must be an even number in 4..{}", scene,
                            slices, kMaxSlices));
  }
}

// Rotation by `angle` radians counter-clockwise about unit `axis` (Rodrigues).
glm::dmat3 axis_rotation(const glm::dvec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  const glm::dmat3 k(0.0, axis.z, -axis.y, -axis.z, 0.0, axis.x, axis.y, -axis.x, 0.0);
  return glm::dmat3(1.0) + s * k + (1.0 - c) * (k * k);
}

// Rotation taking +z to unit `dir`.
glm::dmat3 rotation_from_z(const glm::dvec3& dir) {
  const glm::dvec3 z(0.0, 0.0, 1.0);
  if (dir.z >= 1.0) return glm::dmat3(1.0);
  if (dir.z <= -1.0) return axis_rotation({0.0, 1.0, 0.0}, kPi);
  return axis_rotation(glm::normalize(glm::cross(z, dir)), std::acos(dir.z));
}

// SPD balls.c's nine child directions around +z: a trio of directions 120 degrees
// apart, tilted so one of them points up at asin(2/sqrt(6)) from the equator, then
// copied at 0, 120 and 240 degrees about z. This gives 6 children on the equator and
// 3 above it, none facing the parent's parent.
std::array<glm::dvec3, 9> sphereflake_directions() {
  const double d = 1.0 / std::sqrt(2.0);
  const glm::dmat3 tilt = axis_rotation(glm::normalize(glm::dvec3(1.0, -1.0, 0.0)),
                                        std::asin(2.0 / std::sqrt(6.0)));
  const std::array<glm::dvec3, 3> trio{tilt * glm::dvec3(d, d, 0.0),
                                       tilt * glm::dvec3(d, 0.0, -d),
                                       tilt * glm::dvec3(0.0, d, -d)};
  std::array<glm::dvec3, 9> dirs;
  for (int set = 0; set < 3; ++set) {
    const glm::dmat3 turn = axis_rotation({0.0, 0.0, 1.0}, set * 2.0 * kPi / 3.0);
    for (int k = 0; k < 3; ++k) dirs[set * 3 + k] = turn * trio[k];
  }
  return dirs;
}

void add_sphereflake(Scene& s, const std::array<glm::dvec3, 9>& dirs, const glm::dvec3& center,
                     double radius, const glm::dvec3& up, int depth, int slices,
                     std::uint32_t material) {
  add_sphere(s, center, radius, slices, material);
  if (depth == 0) return;
  const glm::dmat3 to_up = rotation_from_z(up);
  // Children touch their parent: centre distance = parent radius + child radius.
  const double child_radius = radius / 3.0;
  for (const glm::dvec3& d : dirs) {
    const glm::dvec3 dir = to_up * d;
    add_sphereflake(s, dirs, center + (radius + child_radius) * dir, child_radius, dir,
                    depth - 1, slices, material);
  }
}

void add_tetra(Scene& s, const glm::dvec3& center, double half_size, int depth,
               std::uint32_t material) {
  // The corners of the cube [center +- half_size] with x*y*z = +1 form a tetrahedron;
  // at each level its four half-size copies sit at those corners (SPD tetra.c).
  static constexpr std::array<glm::dvec3, 4> kCorners{
      glm::dvec3(-1, -1, 1), glm::dvec3(-1, 1, -1), glm::dvec3(1, -1, -1), glm::dvec3(1, 1, 1)};
  if (depth <= 1) {
    for (int omit = 0; omit < 4; ++omit) {
      std::array<glm::dvec3, 3> f;
      for (int k = 0, n = 0; k < 4; ++k) {
        if (k != omit) f[n++] = center + half_size * kCorners[k];
      }
      // Wind each face counter-clockwise seen from outside.
      if (glm::dot(glm::cross(f[1] - f[0], f[2] - f[0]), f[0] - center) < 0.0) {
        std::swap(f[1], f[2]);
      }
      const auto base = static_cast<std::uint32_t>(s.positions.size());
      for (const glm::dvec3& p : f) s.positions.emplace_back(p);
      s.triangles.emplace_back(base, base + 1, base + 2);
      s.material_ids.push_back(material);
    }
    return;
  }
  for (const glm::dvec3& c : kCorners) {
    add_tetra(s, center + 0.5 * half_size * c, 0.5 * half_size, depth - 1, material);
  }
}

// SPD's background, "UNC sky blue".
constexpr glm::dvec3 kSpdBackground{0.078, 0.361, 0.753};

}  // namespace

Scene make_cornell_box(int sphere_slices) {
  check_slices(sphere_slices, "cornell");
  Scene s;
  s.source = "cornell";
  // Cornell's camera: 35 mm focal length, 25 x 25 mm film, looking down +z.
  s.camera.position = {278.0, 273.0, -800.0};
  s.camera.look_at = {278.0, 273.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.vfov_degrees = 2.0 * std::atan(12.5 / 35.0) * 180.0 / kPi;

  // RGB reflectances commonly derived from the measured spectra of the paints. Whitted
  // shading has no indirect light; an ambient term of 15% of the diffuse colour stands
  // in for it, so faces the lamp cannot see are dim rather than black.
  constexpr double kIndirect = 0.15;
  const glm::dvec3 white_kd{0.725, 0.71, 0.68}, red_kd{0.63, 0.065, 0.05}, green_kd{0.14, 0.45, 0.091};
  Material white{.name = "white", .ambient = kIndirect * white_kd, .diffuse = white_kd};
  Material red{.name = "red", .ambient = kIndirect * red_kd, .diffuse = red_kd};
  Material green{.name = "green", .ambient = kIndirect * green_kd, .diffuse = green_kd};
  Material mirror{.name = "mirror", .diffuse = {0.05, 0.05, 0.05}, .reflectance = 0.9};
  Material glass{.name = "glass", .diffuse = {0.0, 0.0, 0.0}, .specular = {1.0, 1.0, 1.0},
                 .shininess = 200.0, .reflectance = 0.1, .transmittance = 0.9, .ior = 1.5};
  const std::uint32_t m_white = add_material(s, white);
  const std::uint32_t m_red = add_material(s, red);
  const std::uint32_t m_green = add_material(s, green);
  const std::uint32_t m_mirror = add_material(s, mirror);
  const std::uint32_t m_glass = add_material(s, glass);

  const glm::dvec3 inside{278.0, 274.4, 279.6};
  using Q = std::array<glm::dvec3, 4>;
  add_quad(s, Q{{{552.8, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 559.2}, {549.6, 0.0, 559.2}}},
           m_white, inside);  // floor
  add_quad(s, Q{{{556.0, 548.8, 0.0}, {556.0, 548.8, 559.2}, {0.0, 548.8, 559.2},
                 {0.0, 548.8, 0.0}}},
           m_white, inside);  // ceiling
  add_quad(s, Q{{{549.6, 0.0, 559.2}, {0.0, 0.0, 559.2}, {0.0, 548.8, 559.2},
                 {556.0, 548.8, 559.2}}},
           m_white, inside);  // back wall
  add_quad(s, Q{{{0.0, 0.0, 559.2}, {0.0, 0.0, 0.0}, {0.0, 548.8, 0.0}, {0.0, 548.8, 559.2}}},
           m_green, inside);  // right wall (x = 0, on the right as the camera sees it)
  add_quad(s, Q{{{552.8, 0.0, 0.0}, {549.6, 0.0, 559.2}, {556.0, 548.8, 559.2},
                 {556.0, 548.8, 0.0}}},
           m_red, inside);  // left wall

  // Each block: its top outline (published, in order) and height; five faces, no bottom.
  auto add_block = [&](const std::array<glm::dvec2, 4>& top, double height,
                       std::uint32_t material) {
    glm::dvec3 centroid(0.0, height / 2.0, 0.0);
    for (const glm::dvec2& p : top) centroid += glm::dvec3(p.x, 0.0, p.y) / 4.0;
    auto outside = [&](const Q& q) {
      const glm::dvec3 c = (q[0] + q[1] + q[2] + q[3]) / 4.0;
      return c + (c - centroid);
    };
    Q roof;
    for (int k = 0; k < 4; ++k) roof[k] = {top[k].x, height, top[k].y};
    add_quad(s, roof, material, outside(roof));
    for (int k = 0; k < 4; ++k) {
      const glm::dvec2 a = top[k], b = top[(k + 1) % 4];
      const Q side{{{a.x, 0.0, a.y}, {a.x, height, a.y}, {b.x, height, b.y}, {b.x, 0.0, b.y}}};
      add_quad(s, side, material, outside(side));
    }
  };
  add_block({{{130.0, 65.0}, {82.0, 225.0}, {240.0, 272.0}, {290.0, 114.0}}}, 165.0, m_white);
  add_block({{{423.0, 247.0}, {265.0, 296.0}, {314.0, 456.0}, {472.0, 406.0}}}, 330.0,
            m_mirror);

  // The glass sphere rests on the middle of the short block's top.
  const double r = 55.0;
  add_sphere(s, {185.5, 165.0 + r, 169.0}, r, sphere_slices, m_glass);

  // The lamp, 343..213 x 227..332 at the ceiling, emitting downwards
  // (cross(edge_u, edge_v) points -y). It sits 0.1 mm below the ceiling so that shadow
  // rays toward it end before they reach the ceiling plane. Warm white: the lamp's
  // measured spectrum rises toward red.
  Light lamp;
  lamp.kind = LightKind::kArea;
  lamp.color = {1.0, 0.85, 0.6};
  lamp.position = {343.0, 548.7, 227.0};
  lamp.edge_u = {0.0, 0.0, 105.0};
  lamp.edge_v = {-130.0, 0.0, 0.0};
  s.lights.push_back(lamp);
  return s;
}

Scene make_sphereflake(int levels, int slices) {
  if (levels < 0 || levels > 5) {
    throw Error(fmt::format("balls:{}: size must be 0..5 (levels of recursion; 9^size spheres "
                            "at the deepest level)",
                            levels));
  }
  check_slices(slices, "balls");
  Scene s;
  s.source = fmt::format("balls:{}", levels);
  s.background = kSpdBackground;
  s.camera.position = {2.1, 1.3, 1.7};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 0.0, 1.0};
  s.camera.vfov_degrees = 45.0;
  // SPD scales each of n lights by 1/sqrt(n) for renderers that do not.
  const double intensity = 1.0 / std::sqrt(3.0);
  for (const glm::dvec3& p : {glm::dvec3(4.0, 3.0, 2.0), glm::dvec3(1.0, -4.0, 4.0),
                              glm::dvec3(-3.0, 1.0, 5.0)}) {
    Light l;
    l.kind = LightKind::kPoint;
    l.position = p;
    l.color = glm::dvec3(intensity);
    s.lights.push_back(l);
  }
  const std::uint32_t floor = add_material(
      s, spd_material("floor", {1.0, 0.75, 0.33}, 0.2, 0.8, 0.0, 0.0, 0.0, 0.0, 1.0));
  const std::uint32_t ball = add_material(
      s, spd_material("ball", {1.0, 0.9, 0.7}, 0.0, 0.5, 0.5, 0.5, 37.0, 0.0, 1.0));
  // The floor: a square 24 units wide, half a unit below the centre of the top sphere.
  add_quad(s, {{{12.0, 12.0, -0.5}, {-12.0, 12.0, -0.5}, {-12.0, -12.0, -0.5},
                {12.0, -12.0, -0.5}}},
           floor, {0.0, 0.0, 1.0});
  add_sphereflake(s, sphereflake_directions(), {0.0, 0.0, 0.0}, 0.5, {0.0, 0.0, 1.0}, levels,
                  slices, ball);
  return s;
}

Scene make_tetra(int levels) {
  if (levels < 1 || levels > 10) {
    throw Error(fmt::format("tetra:{}: size must be 1..10 (levels of recursion; 4^size "
                            "triangles)",
                            levels));
  }
  Scene s;
  s.source = fmt::format("tetra:{}", levels);
  s.background = kSpdBackground;
  // SPD's (Kay and Kajiya's) view; the up vector is not perpendicular to the view
  // direction, cameras orthogonalise it.
  s.camera.position = {1.022846, -3.177154, -2.174512};
  s.camera.look_at = {-0.004103, -0.004103, 0.216539};
  s.camera.up = {-0.816497, -0.816497, 0.816497};
  s.camera.vfov_degrees = 45.0;
  Light l;
  l.kind = LightKind::kPoint;
  l.position = {2.0, -18.0, -5.0};
  s.lights.push_back(l);
  const std::uint32_t red = add_material(
      s, spd_material("tetra", {1.0, 0.2, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0));
  add_tetra(s, {0.0, 0.0, 0.0}, 1.0, levels, red);
  return s;
}

Scene make_stadium(int levels) {
  if (levels < 1 || levels > 10) {
    throw Error(fmt::format("stadium:{}: size must be 1..10 (the tetra's levels of recursion)", levels));
  }
  Scene s = make_tetra(levels);
  s.source = fmt::format("stadium:{}", levels);
  // Looking at the tetrahedron from inside the stadium; SPD's up vector is not kept.
  s.camera.position = {0.0, 0.5, 4.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  const std::uint32_t grey = add_material(
      s, Material{.name = "stadium", .ambient = glm::dvec3(0.1), .diffuse = glm::dvec3(0.5)});
  // The cube [-1000, 1000]^3, 12 triangles; vertex first + 4 (x > 0) + 2 (y > 0) + (z > 0).
  const auto first = static_cast<std::uint32_t>(s.positions.size());
  for (const float x : {-1000.0f, 1000.0f}) {
    for (const float y : {-1000.0f, 1000.0f}) {
      for (const float z : {-1000.0f, 1000.0f}) s.positions.emplace_back(x, y, z);
    }
  }
  static constexpr std::array<glm::uvec3, 12> kFaces{{{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5},
                                                      {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6},
                                                      {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}}};
  for (const glm::uvec3& f : kFaces) {
    s.triangles.push_back(f + first);
    s.material_ids.push_back(grey);
  }
  return s;
}

Scene make_scattered(int count) {
  if (count < 1 || count > kMaxScattered) {
    throw Error(fmt::format("scattered:{}: size must be 1..{} (triangles)", count, kMaxScattered));
  }
  Scene s;
  s.source = fmt::format("scattered:{}", count);
  const std::uint32_t material = add_material(s, Material{.name = "scattered"});
  // A fixed seed: the same name is the same scene on every run and machine that shares
  // the standard library's distributions.
  std::mt19937 rng(5);
  const double reach = 0.04 * std::cbrt(3000.0 / count);
  std::uniform_real_distribution<double> position(0.0, 1.0), offset(-reach, reach);
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 centre = random_vector(position, rng);
    for (int k = 0; k < 3; ++k) s.positions.emplace_back(centre + random_vector(offset, rng));
    const auto v = static_cast<std::uint32_t>(3 * i);
    s.triangles.emplace_back(v, v + 1, v + 2);
    s.material_ids.push_back(material);
  }
  drop_degenerate_triangles(s, s.source);
  s.camera.position = {0.5, 0.6, 3.0};
  s.camera.look_at = {0.5, 0.5, 0.5};
  s.camera.up = {0.0, 1.0, 0.0};
  Light light;
  light.position = {2.0, 3.0, 2.0};
  s.lights.push_back(light);
  return s;
}

std::vector<std::string> builtin_scene_names() {
  return {"cornell", "balls", "tetra", "stadium", "scattered"};
}

bool is_builtin_scene(std::string_view name_and_size) {
  const std::string_view name = name_and_size.substr(0, name_and_size.find(':'));
  for (const std::string& b : builtin_scene_names()) {
    if (b == name) return true;
  }
  return false;
}

Scene make_builtin_scene(std::string_view name_and_size) {
  const std::size_t colon = name_and_size.find(':');
  const std::string_view name = name_and_size.substr(0, colon);
  // No size means the generator's default; every given size, negative ones too, goes to
  // the generator's own range check.
  std::optional<int> size;
  if (colon != std::string_view::npos) {
    const std::string_view digits = name_and_size.substr(colon + 1);
    int value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size()) {
      throw Error(fmt::format("{}: the size after ':' must be a whole number", name_and_size));
    }
    size = value;
  }
  if (name == "cornell") return size ? make_cornell_box(*size) : make_cornell_box();
  if (name == "balls") return size ? make_sphereflake(*size) : make_sphereflake();
  if (name == "tetra") return size ? make_tetra(*size) : make_tetra();
  if (name == "stadium") return size ? make_stadium(*size) : make_stadium();
  if (name == "scattered") return size ? make_scattered(*size) : make_scattered();
  throw Error(fmt::format("unknown built-in scene '{}' (built-ins: {})", name,
                          fmt::join(builtin_scene_names(), ", ")));
}

}  // namespace rpu
