#include "trace_fixtures.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "fp/format.hpp"
#include "kdtree/kd_node.hpp"
#include "render/sampling.hpp"
#include "scene/geometry.hpp"
#include "common/random_vector.hpp"

namespace rpu::test {

std::vector<functional::TraceRay> camera_rays(const Scene& scene, int width, int height) {
  const Bounds b = scene_bounds(scene);
  const glm::dvec3 centre = 0.5 * (b.lo + b.hi);
  const double radius = 0.5 * glm::length(b.hi - b.lo);
  Camera camera = scene.camera;
  if (glm::length(camera.look_at - camera.position) == 0.0 || scene.source == "icosphere") {
    camera.position = centre + radius * glm::dvec3(1.2, 0.9, 1.5);
    camera.look_at = centre;
    camera.up = {0, 1, 0};
    camera.vfov_degrees = 45;
  }
  const CameraModel model(camera, width, height);
  std::vector<functional::TraceRay> rays;
  rays.reserve(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const PrimaryRay r = model.ray(x + 0.5, y + 0.5, {0.5, 0.5});
      rays.push_back(make_ray(r.origin, r.direction));
    }
  }
  return rays;
}

std::vector<functional::TraceRay> random_rays(const Scene& scene, int count, std::uint32_t seed) {
  const Bounds b = scene_bounds(scene);
  const glm::dvec3 margin = 0.1 * (b.hi - b.lo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto point = [&] {
    return b.lo - margin + random_vector(u, rng) * (b.hi - b.lo + 2.0 * margin);
  };
  std::vector<functional::TraceRay> rays;
  rays.reserve(static_cast<std::size_t>(count));
  while (static_cast<int>(rays.size()) < count) {
    const glm::dvec3 o = point(), d = point() - o;
    if (glm::length(d) == 0.0) continue;
    rays.push_back(make_ray(o, glm::normalize(d)));
  }
  return rays;
}

std::vector<functional::TraceRay> split_plane_rays(const functional::SceneImage& si, int count,
                                                   std::uint32_t seed) {
  const glm::dvec3 lo(si.layout.bounds_lo), hi(si.layout.bounds_hi);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.25, 1.25), d(-1.0, 1.0);
  std::vector<functional::TraceRay> rays;
  const std::uint8_t* nodes = si.image.bytes.data() + si.layout.kd_nodes.offset;
  for (std::uint32_t n = 0; n < si.layout.kd_nodes.count && static_cast<int>(rays.size()) < count; ++n) {
    KdNode node;
    std::memcpy(&node, nodes + sizeof(KdNode) * n, sizeof(KdNode));
    if (node.is_leaf()) continue;
    const int a = node.split_axis();
    for (int k = 0; k < 6 && static_cast<int>(rays.size()) < count; ++k) {
      glm::dvec3 o = lo + random_vector(u, rng) * (hi - lo), dir = random_vector(d, rng);
      if (k >= 2) dir[a] = k % 2 ? 0.0 : -0.0;
      if (k == 5) dir = -dir;
      functional::TraceRay r = make_ray(o, dir);
      r.origin[a] = node.split();
      // The box and the splits are in kd space; the ray goes to the unit in world space.
      for (float& x : r.origin) {
        x = std::bit_cast<float>(fp::scale_fp32(std::bit_cast<std::uint32_t>(x), si.layout.kd_scale_exponent));
      }
      rays.push_back(r);
    }
  }
  return rays;
}

DoubleHit double_hit(const Scene& s, std::uint32_t prim, const functional::TraceRay& r) {
  const glm::dvec3 a(s.positions[s.triangles[prim].x]), b(s.positions[s.triangles[prim].y]),
      c(s.positions[s.triangles[prim].z]);
  const glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.direction[0], r.direction[1], r.direction[2]);
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2), q = glm::cross(o - a, e1);
  const double det = glm::dot(e1, p);
  const double u = glm::dot(o - a, p) / det, v = glm::dot(d, q) / det, w = 1.0 - u - v;
  // A barycentric coordinate times its vertex's height over the opposite edge is the
  // point's distance from that edge.
  const double twice_area = glm::length(glm::cross(e1, e2));
  const double edge_distance = std::min({w * twice_area / glm::length(c - b), u * twice_area / glm::length(e2),
                                         v * twice_area / glm::length(e1)});
  const double cosine = std::abs(glm::dot(glm::cross(e1, e2) / twice_area, glm::normalize(d)));
  return {glm::dot(e2, q) / det, std::min({u, v, w}), edge_distance, 16.0 * 0x1p-24 * glm::length(a - o) / cosine};
}

}  // namespace rpu::test
