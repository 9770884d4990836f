#pragma once

// Scenes and rays for the trace-unit tests.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "scene/scene.hpp"

namespace rpu::test {

// A closed, consistently wound icosphere of radius 1 (shared vertices, every edge in
// exactly two triangles): nothing may leak out of it.
inline Scene icosphere(int subdivisions) {
  Scene s;
  s.source = "icosphere";
  s.materials.push_back({});
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                               {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  for (auto& x : v) x = glm::normalize(x);
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
                               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
                               {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto midpoint = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace({key.first, key.second}, static_cast<unsigned>(v.size()));
      if (inserted) v.push_back(glm::normalize(v[a] + v[b]));
      return it->second;
    };
    std::vector<glm::uvec3> next;
    for (const glm::uvec3 t : f) {
      const unsigned a = midpoint(t.x, t.y), b = midpoint(t.y, t.z), c = midpoint(t.z, t.x);
      next.insert(next.end(), {{t.x, a, c}, {t.y, b, a}, {t.z, c, b}, {a, b, c}});
    }
    f = std::move(next);
  }
  for (const auto& x : v) s.positions.emplace_back(x);
  s.triangles = f;
  s.material_ids.assign(f.size(), 0);
  return s;
}

// An axis-aligned cube [-1, 1]^3 of 12 outward-facing triangles.
inline Scene cube() {
  Scene s;
  s.source = "cube";
  s.materials.push_back({});
  for (int x : {-1, 1})
    for (int y : {-1, 1})
      for (int z : {-1, 1}) s.positions.emplace_back(x, y, z);
  // Vertex index = 4*(x>0) + 2*(y>0) + (z>0).
  s.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                 {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  s.material_ids.assign(12, 0);
  return s;
}

inline functional::TraceRay make_ray(glm::dvec3 o, glm::dvec3 d, float t_min = 0.0f) {
  functional::TraceRay r;
  for (int i = 0; i < 3; ++i) {
    r.origin[i] = static_cast<float>(o[i]);
    r.direction[i] = static_cast<float>(d[i]);
  }
  r.t_min = t_min;
  return r;
}

// A ray/triangle hit in double precision, as an independent judge of near ties: of the
// ray's meeting with the triangle's plane, the distance t, the smallest barycentric
// coordinate (< 0 outside the triangle, ~0 on an edge) and the distance from the nearest
// edge in scene units (< 0 outside). fp32_reach bounds how far fp32 rounding can move
// the meeting point, along the ray and so within the plane: a plane distance formed from
// rounded coordinates is off by a few ulps of the coordinates it subtracts, divided by
// the cosine of the incidence angle, 16 u |A - O| / |cos| with u = 2^-24
// (docs/traversal.md, "Accuracy"). Within it of an edge, an fp32 test may fall on either
// side.
struct DoubleHit {
  double t, min_barycentric, edge_distance, fp32_reach;
};
DoubleHit double_hit(const Scene& scene, std::uint32_t prim, const functional::TraceRay& ray);

// Camera rays over the scene's bounding box from a diagonal viewpoint, and random rays
// between random points of the (slightly enlarged) box.
std::vector<functional::TraceRay> camera_rays(const Scene& scene, int width, int height);
std::vector<functional::TraceRay> random_rays(const Scene& scene, int count, std::uint32_t seed);

// Rays whose origins lie exactly on the split planes of the image's kd tree (the split
// word itself, not a rounding of it), six per inner node in node order until `count`:
// random directions, then the split axis' component +0 and -0 (the ray runs in the
// plane), then reversed. The other coordinates are random over 1.5x the scene's box.
std::vector<functional::TraceRay> split_plane_rays(const functional::SceneImage& si, int count,
                                                   std::uint32_t seed);

}  // namespace rpu::test
