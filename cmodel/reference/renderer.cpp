#include "reference/renderer.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include "common/host_threads.hpp"
#include "scene/geometry.hpp"

namespace rpu {

namespace {
constexpr int kTileSize = 16;
constexpr double kEpsilonFraction = 1e-4;

double scene_diagonal(const Scene& scene) {
  const Bounds bounds = scene_bounds(scene);
  const double d = bounds.empty() ? 0.0 : glm::length(bounds.hi - bounds.lo);
  return d > 0.0 ? d : 1.0;
}

glm::dvec3 reflect(const glm::dvec3& d, const glm::dvec3& n) { return d - 2.0 * glm::dot(d, n) * n; }
}  // namespace

ReferenceRenderer::ReferenceRenderer(const Scene& scene)
    : scene_(scene), bvh_(scene), epsilon_(kEpsilonFraction * scene_diagonal(scene)) {}

glm::dvec3 ReferenceRenderer::trace(const Ray& ray, int depth, int max_depth, SampleStream& stream,
                                    RayCounts& counts) const {
  const Hit hit = bvh_.closest_hit(ray);
  if (!hit.hit()) return scene_.background;
  return shade(ray, hit, depth, max_depth, stream, counts);
}

glm::dvec3 ReferenceRenderer::shade(const Ray& ray, const Hit& hit, int depth, int max_depth,
                                    SampleStream& stream, RayCounts& counts) const {
  const glm::uvec3 tri = scene_.triangles[hit.prim];
  const Material& m = scene_.materials[scene_.material_ids[hit.prim]];
  const glm::dvec3 p0(scene_.positions[tri.x]), p1(scene_.positions[tri.y]), p2(scene_.positions[tri.z]);
  const glm::dvec3 d = ray.direction;
  const glm::dvec3 p = ray.origin + hit.t * d;

  // Geometric normal, and the shading normal turned to its side (docs/shading.md §2).
  glm::dvec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  glm::dvec3 n = ng;
  if (!scene_.normals.empty()) {
    const double w = 1.0 - hit.u - hit.v;
    const glm::dvec3 s = w * glm::dvec3(scene_.normals[tri.x]) + hit.u * glm::dvec3(scene_.normals[tri.y]) +
                         hit.v * glm::dvec3(scene_.normals[tri.z]);
    if (glm::dot(s, s) > 0.0) n = glm::normalize(s);
    if (glm::dot(n, ng) < 0.0) n = -n;
  }
  const bool entering = glm::dot(d, ng) < 0.0;
  if (!entering) {
    ng = -ng;
    n = -n;
  }
  const glm::dvec3 v = -d;
  const glm::dvec3 above = p + epsilon_ * ng;  // origin for rays leaving on the viewer's side

  glm::dvec3 color = m.ambient;
  for (const Light& light : scene_.lights) {
    glm::dvec3 l;
    double distance = std::numeric_limits<double>::infinity();
    if (light.kind == LightKind::kDirectional) {
      l = -light.direction;
    } else {
      const bool area = light.kind == LightKind::kArea;
      const double s = area ? stream.next_double() : 0.0;
      const double t = area ? stream.next_double() : 0.0;
      l = light_sample_point(light, s, t) - p;
      distance = glm::length(l);
      l /= distance;
    }
    const double n_dot_l = glm::dot(n, l);
    if (n_dot_l <= 0.0 || glm::dot(ng, l) <= 0.0) continue;
    ++counts.shadow;
    if (bvh_.any_hit({above, l, 0.0, distance - epsilon_})) continue;
    const glm::dvec3 r = 2.0 * n_dot_l * n - l;
    const double r_dot_v = std::max(0.0, glm::dot(r, v));
    const double specular = r_dot_v > 0.0 ? std::pow(r_dot_v, m.shininess) : 0.0;
    color += light.color * (m.diffuse * n_dot_l + m.specular * specular);
  }

  if (depth >= max_depth) return color;
  if (m.reflectance > 0.0) {
    ++counts.reflection;
    color += m.reflectance * trace({above, reflect(d, n)}, depth + 1, max_depth, stream, counts);
  }
  if (m.transmittance > 0.0) {
    const double eta = entering ? 1.0 / m.ior : m.ior;
    const double cos_i = -glm::dot(d, n);
    const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if (k < 0.0) {  // total internal reflection: the transmitted weight is reflected
      ++counts.reflection;
      color += m.transmittance * trace({above, reflect(d, n)}, depth + 1, max_depth, stream, counts);
    } else {
      ++counts.refraction;
      const glm::dvec3 t = glm::normalize(eta * d + (eta * cos_i - std::sqrt(k)) * n);
      color += m.transmittance * trace({p - epsilon_ * ng, t}, depth + 1, max_depth, stream, counts);
    }
  }
  return color;
}

Image ReferenceRenderer::render(const RenderSettings& settings, RayCounts* counts,
                                const ProgressCallback& progress) const {
  Image image(settings.width, settings.height);
  const CameraModel camera(scene_.camera, settings.width, settings.height);
  const int tiles_x = (settings.width + kTileSize - 1) / kTileSize;
  const int tiles_y = (settings.height + kTileSize - 1) / kTileSize;
  const std::size_t tile_count = static_cast<std::size_t>(tiles_x) * tiles_y;
  std::atomic<std::size_t> next_tile{0}, done_tiles{0};

  auto worker = [&](RayCounts& local) {
    for (std::size_t tile; (tile = next_tile.fetch_add(1)) < tile_count;) {
      const int x0 = static_cast<int>(tile % tiles_x) * kTileSize;
      const int y0 = static_cast<int>(tile / tiles_x) * kTileSize;
      for (int y = y0; y < std::min(y0 + kTileSize, settings.height); ++y) {
        for (int x = x0; x < std::min(x0 + kTileSize, settings.width); ++x) {
          glm::dvec3 sum(0.0);
          const auto pixel = static_cast<std::uint32_t>(y * settings.width + x);
          for (int s = 0; s < settings.spp; ++s) {
            SampleStream stream(settings.seed, pixel, static_cast<std::uint32_t>(s));
            const glm::dvec2 offset = pixel_sample_offset(s, settings.spp, stream);
            const glm::dvec2 lens{stream.next_double(), stream.next_double()};
            const PrimaryRay ray = camera.ray(x + offset.x, y + offset.y, lens);
            ++local.primary;
            sum += trace({ray.origin, ray.direction}, 0, settings.max_depth, stream, local);
          }
          image.at(x, y) = glm::vec3(sum / static_cast<double>(settings.spp));
        }
      }
      const std::size_t done = done_tiles.fetch_add(1) + 1;
      if (progress) progress(done, tile_count);
    }
  };

  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  const auto thread_count = static_cast<std::size_t>(settings.threads > 0 ? settings.threads : hardware);
  std::vector<RayCounts> per_thread(thread_count);
  run_host_threads(static_cast<int>(thread_count),
                   [&](int i) { worker(per_thread[static_cast<std::size_t>(i)]); });
  if (counts) {
    *counts = {};
    for (const RayCounts& c : per_thread) *counts += c;
  }
  return image;
}

}  // namespace rpu
