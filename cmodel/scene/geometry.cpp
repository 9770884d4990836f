#include "scene/geometry.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace rpu {

glm::dvec3 light_sample_point(const Light& light, double s, double t) {
  if (light.kind != LightKind::kArea) return light.position;
  return light.position + (s * light.edge_u + t * light.edge_v);
}

Bounds scene_bounds(const Scene& scene) {
  Bounds box;
  for (const glm::uvec3& t : scene.triangles) {
    for (int k = 0; k < 3; ++k) box.extend(glm::dvec3(scene.positions[t[k]]));
  }
  return box;
}

namespace {

enum class Degeneracy { kNone, kZeroArea, kThin };

Degeneracy classify(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  // Double precision: the products of fp32 differences are exact enough here.
  const glm::dvec3 pa(a), pb(b), pc(c);
  const glm::dvec3 e1 = pb - pa, e2 = pc - pa, e3 = pc - pb;
  const double twice_area = glm::length(glm::cross(e1, e2));
  if (twice_area == 0.0) return Degeneracy::kZeroArea;
  const double longest2 = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
  return twice_area <= kDegenerateRatio * longest2 ? Degeneracy::kThin : Degeneracy::kNone;
}

// Gives every triangle its own three vertices carrying the face normal.
void make_flat_normals(Scene& g) {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  positions.reserve(g.triangles.size() * 3);
  normals.reserve(g.triangles.size() * 3);
  for (glm::uvec3& t : g.triangles) {
    const glm::vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    const glm::vec3 n = glm::vec3(glm::normalize(glm::cross(glm::dvec3(b - a), glm::dvec3(c - a))));
    const auto base = static_cast<std::uint32_t>(positions.size());
    for (int k = 0; k < 3; ++k) {
      positions.push_back(g.positions[t[k]]);
      normals.push_back(n);
      if (!g.uvs.empty()) uvs.push_back(g.uvs[t[k]]);
    }
    t = glm::uvec3(base, base + 1, base + 2);
  }
  g.positions = std::move(positions);
  g.normals = std::move(normals);
  g.uvs = std::move(uvs);
}

}  // namespace

bool is_degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return classify(a, b, c) != Degeneracy::kNone;
}

std::size_t drop_degenerate_triangles(Scene& part, const std::string& name) {
  std::size_t zero_area = 0, thin = 0, kept = 0;
  for (std::size_t i = 0; i < part.triangles.size(); ++i) {
    const glm::uvec3 t = part.triangles[i];
    switch (classify(part.positions[t.x], part.positions[t.y], part.positions[t.z])) {
      case Degeneracy::kZeroArea: ++zero_area; continue;
      case Degeneracy::kThin: ++thin; continue;
      case Degeneracy::kNone: break;
    }
    part.triangles[kept] = t;
    part.material_ids[kept] = part.material_ids[i];
    ++kept;
  }
  part.triangles.resize(kept);
  part.material_ids.resize(kept);
  const std::size_t dropped = zero_area + thin;
  if (dropped != 0) {
    std::string why;
    if (zero_area != 0) why = fmt::format("{} zero area", zero_area);
    if (thin != 0) why += fmt::format("{}{} needle or collinear", why.empty() ? "" : ", ", thin);
    part.warnings.push_back(
        fmt::format("{}: dropped {} degenerate triangles ({})", name, dropped, why));
  }
  return dropped;
}

namespace {

// A vertex's attributes as bit patterns, -0 read as +0, for exact comparison.
struct VertexKey {
  std::array<std::uint32_t, 8> words{};
  bool operator==(const VertexKey&) const = default;
};

struct VertexKeyHash {
  std::size_t operator()(const VertexKey& k) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the words
    for (const std::uint32_t w : k.words) h = (h ^ w) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

std::uint32_t key_bits(float x) { return std::bit_cast<std::uint32_t>(x == 0.0f ? 0.0f : x); }

VertexKey position_key(const glm::vec3& p) { return {{key_bits(p.x), key_bits(p.y), key_bits(p.z)}}; }

}  // namespace

void weld_identical_vertices(Scene& part) {
  std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> first;
  first.reserve(part.positions.size());
  std::vector<std::uint32_t> remap(part.positions.size());
  std::size_t kept = 0;
  for (std::size_t v = 0; v < part.positions.size(); ++v) {
    VertexKey key = position_key(part.positions[v]);
    if (!part.normals.empty()) {
      for (int c = 0; c < 3; ++c) key.words[3 + c] = key_bits(part.normals[v][c]);
    }
    if (!part.uvs.empty()) {
      for (int c = 0; c < 2; ++c) key.words[6 + c] = key_bits(part.uvs[v][c]);
    }
    const auto [at, inserted] = first.try_emplace(key, static_cast<std::uint32_t>(kept));
    if (inserted) {
      part.positions[kept] = part.positions[v];
      if (!part.normals.empty()) part.normals[kept] = part.normals[v];
      if (!part.uvs.empty()) part.uvs[kept] = part.uvs[v];
      ++kept;
    }
    remap[v] = at->second;
  }
  part.positions.resize(kept);
  if (!part.normals.empty()) part.normals.resize(kept);
  if (!part.uvs.empty()) part.uvs.resize(kept);
  for (glm::uvec3& t : part.triangles) t = glm::uvec3(remap[t.x], remap[t.y], remap[t.z]);
}

void generate_smooth_normals(Scene& part) {
  std::unordered_map<VertexKey, glm::dvec3, VertexKeyHash> sums;
  for (const glm::uvec3& t : part.triangles) {
    const glm::dvec3 a(part.positions[t.x]), b(part.positions[t.y]), c(part.positions[t.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) continue;  // degenerate: dropped later
    for (int k = 0; k < 3; ++k) sums[position_key(part.positions[t[k]])] += n / len;
  }
  part.normals.assign(part.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
  for (std::size_t v = 0; v < part.positions.size(); ++v) {
    const auto s = sums.find(position_key(part.positions[v]));
    if (s == sums.end()) continue;
    const double len = glm::length(s->second);
    if (len > 0.0 && std::isfinite(len)) part.normals[v] = glm::vec3(s->second / len);
  }
}

void scale_scene(Scene& scene, int exponent) {
  const auto scaled = [exponent](double x) { return std::ldexp(x, exponent); };
  const auto scaled3 = [exponent](const glm::dvec3& v) {
    return glm::dvec3(std::ldexp(v.x, exponent), std::ldexp(v.y, exponent), std::ldexp(v.z, exponent));
  };
  for (glm::vec3& p : scene.positions) {
    p = glm::vec3(std::ldexp(p.x, exponent), std::ldexp(p.y, exponent), std::ldexp(p.z, exponent));
  }
  Camera& c = scene.camera;
  c.position = scaled3(c.position);
  c.look_at = scaled3(c.look_at);
  c.aperture_radius = scaled(c.aperture_radius);
  c.focus_distance = scaled(c.focus_distance);
  for (Light& l : scene.lights) {
    l.position = scaled3(l.position);
    l.edge_u = scaled3(l.edge_u);
    l.edge_v = scaled3(l.edge_v);
  }
}

void translate_scene(Scene& scene, const glm::dvec3& offset) {
  for (glm::vec3& p : scene.positions) p = glm::vec3(glm::dvec3(p) + offset);
  scene.camera.position += offset;
  scene.camera.look_at += offset;
  for (Light& l : scene.lights) l.position += offset;
}

void append_geometry(Scene& scene, Scene&& part) {
  for (std::string& w : part.warnings) scene.warnings.push_back(std::move(w));
  if (part.triangles.empty()) return;
  if (scene.triangles.empty()) {
    scene.positions.clear();
    scene.normals.clear();
    scene.uvs.clear();
  }
  const bool scene_has_geometry = !scene.triangles.empty();
  if (scene_has_geometry && scene.normals.empty() != part.normals.empty()) {
    make_flat_normals(scene.normals.empty() ? scene : part);
  }
  if (scene_has_geometry && scene.uvs.empty() != part.uvs.empty()) {
    Scene& missing = scene.uvs.empty() ? scene : part;
    missing.uvs.assign(missing.positions.size(), glm::vec2(0.0f));
  }
  const auto base = static_cast<std::uint32_t>(scene.positions.size());
  scene.positions.insert(scene.positions.end(), part.positions.begin(), part.positions.end());
  scene.normals.insert(scene.normals.end(), part.normals.begin(), part.normals.end());
  scene.uvs.insert(scene.uvs.end(), part.uvs.begin(), part.uvs.end());
  for (const glm::uvec3& t : part.triangles) scene.triangles.push_back(t + base);
  scene.material_ids.insert(scene.material_ids.end(), part.material_ids.begin(),
                            part.material_ids.end());
}

}  // namespace rpu
