#include "sweep/ray_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <random>

#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "reference/bvh.hpp"
#include "render/sampling.hpp"

namespace rpu::sweep {
namespace {

functional::TraceRay trace_ray(const glm::dvec3& origin, const glm::dvec3& direction) {
  functional::TraceRay r;
  for (int i = 0; i < 3; ++i) {
    r.origin[i] = static_cast<float>(origin[i]);
    r.direction[i] = static_cast<float>(direction[i]);
  }
  return r;
}

// Union-find over triangles.
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Crossings of the ray (origin, direction), t > 0, with the triangles: Moeller-Trumbore in
// double, a hit exactly on an edge counted for neither side (the caller asks three
// directions and needs all to agree).
int crossings(const Scene& mesh, const glm::dvec3& origin, const glm::dvec3& direction) {
  int count = 0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 v0(mesh.positions[t.x]), e1 = glm::dvec3(mesh.positions[t.y]) - v0,
        e2 = glm::dvec3(mesh.positions[t.z]) - v0;
    const glm::dvec3 p = glm::cross(direction, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    const glm::dvec3 s = origin - v0;
    const double u = glm::dot(s, p) / det;
    if (u <= 0.0 || u >= 1.0) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(direction, q) / det;
    if (v <= 0.0 || u + v >= 1.0) continue;
    count += glm::dot(e2, q) / det > 0.0 ? 1 : 0;
  }
  return count;
}

bool inside(const Scene& mesh, const glm::dvec3& point) {
  constexpr std::array<glm::dvec3, 3> kDirections{glm::dvec3(0.5773, 0.5411, 0.6113), glm::dvec3(-0.7071, 0.3183, -0.6309),
                                                  glm::dvec3(0.1414, -0.9273, 0.3466)};
  return std::all_of(kDirections.begin(), kDirections.end(),
                     [&](const glm::dvec3& d) { return crossings(mesh, point, d) % 2 == 1; });
}

// A point inside the closed mesh: its vertices' centroid, else a point just behind one of
// its triangles (on either side); none when no candidate passes the parity test.
std::optional<glm::dvec3> inside_point(const Scene& mesh) {
  glm::dvec3 centroid(0.0), lo(mesh.positions.front()), hi(mesh.positions.front());
  for (const glm::vec3& p : mesh.positions) {
    centroid += glm::dvec3(p);
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  centroid /= static_cast<double>(mesh.positions.size());
  if (inside(mesh, centroid)) return centroid;
  const double step = 1e-3 * glm::length(hi - lo);
  const std::size_t stride = std::max<std::size_t>(1, mesh.triangles.size() / 16);
  for (std::size_t i = 0; i < mesh.triangles.size(); i += stride) {
    const glm::uvec3 t = mesh.triangles[i];
    const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
    for (const double side : {-1.0, 1.0}) {
      const glm::dvec3 candidate = (a + b + c) / 3.0 + side * step * n;
      if (inside(mesh, candidate)) return candidate;
    }
  }
  return std::nullopt;
}

// Rays from `origin` (inside) to points of the mesh's edges and to its vertices, traced
// any-hit against the mesh alone; the count of those that hit nothing.
std::uint64_t count_leaks(const Scene& mesh, const glm::dvec3& origin, const KdBuildConfig& build, IsectMode mode,
                          std::uint64_t rays, std::mt19937_64& rng) {
  const functional::SceneImage si = functional::make_scene_image(mesh, build, mode);
  const functional::Tracer tracer(si.image.bytes, si.layout, build.format, build.stack_depth);
  std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
  std::uniform_int_distribution<int> corner(0, 2);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  std::uint64_t leaks = 0;
  for (std::uint64_t i = 0; i < rays; ++i) {
    const glm::uvec3 t = mesh.triangles[pick(rng)];
    const int k = corner(rng);
    const glm::dvec3 a(mesh.positions[t[k]]), b(mesh.positions[t[(k + 1) % 3]]);
    const double s = i % 8 == 0 ? 0.0 : along(rng);  // every 8th ray at a vertex
    leaks += tracer.trace(trace_ray(origin, a + s * (b - a) - origin), functional::TraceMode::kAny).hit ? 0 : 1;
  }
  return leaks;
}

}  // namespace

std::vector<Scene> closed_meshes(const Scene& world) {
  // Weld vertices by position, then join triangles that share an edge.
  std::map<std::array<float, 3>, std::uint32_t> weld;
  std::vector<std::uint32_t> vertex(world.positions.size());
  for (std::size_t i = 0; i < world.positions.size(); ++i) {
    const glm::vec3& p = world.positions[i];
    vertex[i] = weld.try_emplace({p.x, p.y, p.z}, static_cast<std::uint32_t>(weld.size())).first->second;
  }
  const std::size_t n = world.triangles.size();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edges;
  std::vector<bool> degenerate(n, false);
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::uvec3 t = world.triangles[i];
    const std::uint32_t w[3] = {vertex[t.x], vertex[t.y], vertex[t.z]};
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
      degenerate[i] = true;
      continue;
    }
    for (int k = 0; k < 3; ++k) edges[std::minmax(w[k], w[(k + 1) % 3])].push_back(i);
  }
  for (const auto& [edge, tris] : edges) {
    for (const std::uint32_t t : tris) parent[root(parent, t)] = root(parent, tris.front());
  }
  std::vector<bool> open(n, false);
  for (const auto& [edge, tris] : edges) {
    if (tris.size() != 2) open[root(parent, tris.front())] = true;
  }
  std::map<std::uint32_t, Scene> parts;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t r = root(parent, i);
    if (degenerate[i] || open[r]) continue;
    Scene& part = parts[r];
    const glm::uvec3 t = world.triangles[i];
    const auto base = static_cast<std::uint32_t>(part.positions.size());
    for (int k = 0; k < 3; ++k) part.positions.push_back(world.positions[t[k]]);
    part.triangles.emplace_back(base, base + 1, base + 2);
    part.material_ids.push_back(world.material_ids.empty() ? 0 : world.material_ids[i]);
  }
  std::vector<Scene> out;
  for (auto& [r, part] : parts) {
    if (part.triangles.size() < 4) continue;
    part.source = world.source;
    part.camera = world.camera;
    part.lights = world.lights;
    part.materials = world.materials;
    part.background = world.background;
    out.push_back(std::move(part));
  }
  return out;
}

RayChecks check_rays(const Scene& world, const KdBuildConfig& build, IsectMode mode, int width, int height,
                     bool hit_check, std::uint32_t leak_rays, std::uint64_t seed, std::uint32_t extreme_rays) {
  RayChecks out;
  if (hit_check || extreme_rays > 0) {
    const Scene scene = functional::chip_space_scene(world, build.format);
    const functional::SceneImage si = functional::make_scene_image(scene, build, mode);
    const functional::Tracer tracer(si.image.bytes, si.layout, build.format, build.stack_depth);
    const ReferenceBvh bvh(scene);
    // The units and the fp64 trace on the same (fp32) ray: 1 when they disagree.
    const auto mismatch = [&](const functional::TraceRay& r) -> std::uint64_t {
      Ray d;
      for (int i = 0; i < 3; ++i) {
        d.origin[i] = r.origin[i];
        d.direction[i] = r.direction[i];
      }
      d.t_min = r.t_min;
      const functional::TraceHit unit = tracer.trace(r, functional::TraceMode::kClosest);
      const Hit exact = bvh.closest_hit(d);
      return unit.hit != exact.hit() || (unit.hit && unit.prim != exact.prim) ? 1 : 0;
    };
    if (hit_check) {
      const CameraModel camera(scene.camera, width, height);
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const PrimaryRay p = camera.ray(x + 0.5, y + 0.5, {0.5, 0.5});
          out.hit_mismatches += mismatch(trace_ray(p.origin, p.direction));
          ++out.primary_rays;
        }
      }
    }
    if (extreme_rays > 0 && !scene.triangles.empty()) {
      glm::dvec3 lo(scene.positions.front()), hi = lo;
      for (const glm::vec3& p : scene.positions) {
        lo = glm::min(lo, glm::dvec3(p));
        hi = glm::max(hi, glm::dvec3(p));
      }
      const double far = 2.0 * glm::length(hi - lo);
      std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
      std::uniform_int_distribution<std::size_t> pick(0, scene.triangles.size() - 1);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (std::uint32_t i = 0; i < extreme_rays; ++i) {
        const glm::uvec3 t = scene.triangles[pick(rng)];
        const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
        const glm::dvec3 centroid = (a + b + c) / 3.0, n = glm::normalize(glm::cross(b - a, c - a));
        const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
        // Axis-parallel: along the axis nearest the normal, every other coordinate the
        // centroid's own.
        int k = 0;
        for (int j = 1; j < 3; ++j) k = std::abs(n[j]) > std::abs(n[k]) ? j : k;
        glm::dvec3 axis(0.0);
        axis[k] = side;
        glm::dvec3 origin = centroid;
        origin[k] -= side * far;
        out.axis_mismatches += mismatch(trace_ray(origin, axis));
        // Grazing: along an edge, tilted 1e-3 radians towards the plane's side.
        const glm::dvec3 graze = glm::normalize(glm::normalize(b - a) + side * 1e-3 * n);
        out.grazing_mismatches += mismatch(trace_ray(centroid - far * graze, graze));
        // From the surface: a point of the triangle, leaving into one half-space.
        double u = unit(rng), v = unit(rng);
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        glm::dvec3 leave(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
        leave = glm::normalize(leave - glm::dot(leave, n) * n) + side * (0.1 + unit(rng)) * n;
        out.surface_mismatches += mismatch(trace_ray(a + u * (b - a) + v * (c - a), glm::normalize(leave)));
      }
      out.axis_rays = out.grazing_rays = out.surface_rays = extreme_rays;
    }
  }
  if (leak_rays == 0) return out;
  std::vector<std::pair<Scene, glm::dvec3>> meshes;
  for (Scene& mesh : closed_meshes(world)) {
    Scene chip = functional::chip_space_scene(mesh, build.format);
    if (const std::optional<glm::dvec3> origin = inside_point(chip)) meshes.emplace_back(std::move(chip), *origin);
  }
  out.closed_meshes = meshes.size();
  std::mt19937_64 rng(seed);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    // leak_rays shared out, the first meshes taking one more where it does not divide.
    const std::uint64_t rays = leak_rays / meshes.size() + (i < leak_rays % meshes.size() ? 1 : 0);
    out.leaks += count_leaks(meshes[i].first, meshes[i].second, build, mode, rays, rng);
    out.leak_rays += rays;
  }
  return out;
}

}  // namespace rpu::sweep
