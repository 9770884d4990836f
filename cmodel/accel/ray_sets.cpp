#include "accel/ray_sets.hpp"

#include <limits>
#include <random>

#include "common/random_vector.hpp"
#include "render/sampling.hpp"
#include "scene/geometry.hpp"

namespace rpu::accel {

std::vector<Ray> primary_rays(const Scene& scene, int width, int height) {
  const CameraModel camera(scene.camera, width, height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const PrimaryRay r = camera.ray(x + 0.5, y + 0.5, {0.5, 0.5});
      rays.push_back({r.origin, r.direction});
    }
  }
  return rays;
}

std::vector<Ray> random_rays(const TriangleSet& triangles, int count, std::uint32_t seed) {
  // An empty scene still gets rays, through the unit box.
  const Bounds& b = triangles.bounds();
  const glm::dvec3 lo = b.empty() ? glm::dvec3(-1.0) : b.lo, hi = b.empty() ? glm::dvec3(1.0) : b.hi;
  const glm::dvec3 margin = 0.1 * (hi - lo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto point = [&] { return lo - margin + random_vector(unit, rng) * (hi - lo + 2.0 * margin); };
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(count));
  while (static_cast<int>(rays.size()) < count) {
    const glm::dvec3 from = point();
    const glm::dvec3 to = point();
    const double length = glm::length(to - from);
    if (length > 0.0) rays.push_back({from, (to - from) / length});
  }
  return rays;
}

std::vector<Ray> shadow_rays(const Scene& scene, const TriangleSet& triangles, std::span<const Ray> rays,
                             std::span<const Hit> hits, std::uint32_t seed) {
  constexpr double kLiftFraction = 1e-4;  // the reference renderer's kEpsilonFraction
  const Bounds& b = triangles.bounds();
  const double lift = b.empty() ? 0.0 : kLiftFraction * glm::length(b.hi - b.lo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Ray> shadows;
  for (std::size_t i = 0; i < rays.size() && i < hits.size(); ++i) {
    if (!hits[i].hit()) continue;
    const glm::uvec3 tri = scene.triangles[hits[i].prim];
    const glm::dvec3 a(scene.positions[tri.x]), e1 = glm::dvec3(scene.positions[tri.y]) - a,
        e2 = glm::dvec3(scene.positions[tri.z]) - a;
    glm::dvec3 normal = glm::normalize(glm::cross(e1, e2));
    if (glm::dot(normal, rays[i].direction) > 0.0) normal = -normal;
    const glm::dvec3 above = rays[i].origin + hits[i].t * rays[i].direction + lift * normal;
    for (const Light& light : scene.lights) {
      glm::dvec3 to_light;
      double distance = std::numeric_limits<double>::infinity();
      if (light.kind == LightKind::kDirectional) {
        to_light = -light.direction;
      } else {
        const bool area = light.kind == LightKind::kArea;
        const double s = area ? unit(rng) : 0.0;
        const double t = area ? unit(rng) : 0.0;
        to_light = light_sample_point(light, s, t) - above;
        distance = glm::length(to_light);
        if (!(distance > lift)) continue;
        to_light /= distance;
      }
      if (!(glm::dot(normal, to_light) > 0.0)) continue;
      shadows.push_back({above, to_light, 0.0, distance - lift});
    }
  }
  return shadows;
}

}  // namespace rpu::accel
