#include "accel/beam.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "accel/bvh.hpp"
#include "common/error.hpp"

namespace rpu::accel {

namespace {
// Added to every plane's margin: more than the rounding of a plane test, n.(q - o), of
// about 1e-16 of |q - o|, and far less than any angle a frustum plane cuts off.
constexpr double kMarginSlack = 1e-9;
// A plane that leaves a ray of the beam outside by more than this cosine is not one of
// the beam's (its corners were not the beam's outermost rays): it is not kept.
constexpr double kMostOutside = 1e-6;
}  // namespace

Frustum::Frustum(std::span<const Ray> rays, const std::array<std::size_t, 4>& corners) {
  if (rays.empty()) return;
  origin_ = rays.front().origin;
  for (const Ray& r : rays) {
    if (r.origin != origin_) return;
  }
  glm::dvec3 mean(0.0);
  for (const Ray& r : rays) mean += glm::normalize(r.direction);
  for (std::size_t k = 0; k < 4; ++k) {
    const glm::dvec3 n = glm::cross(rays[corners[k]].direction, rays[corners[(k + 1) % 4]].direction);
    if (!(glm::length(n) > 0.0)) continue;
    glm::dvec3 normal = glm::normalize(n);
    if (glm::dot(normal, mean) < 0.0) normal = -normal;
    // How far outside the plane, as a cosine, rounding puts a ray of the beam.
    double outside = 0.0;
    for (const Ray& r : rays) outside = std::max(outside, -glm::dot(normal, glm::normalize(r.direction)));
    if (outside > kMostOutside) continue;
    normals_[static_cast<std::size_t>(planes_)] = normal;
    margins_[static_cast<std::size_t>(planes_)] = outside + kMarginSlack;
    ++planes_;
  }
}

template <std::size_t N>
bool Frustum::beyond_a_plane(const std::array<glm::dvec3, N>& points) const {
  // A point q beyond plane k by more than its margin: n.(q - o) < -margin |q - o|. Those
  // points form a convex cone, so a box or triangle whose corners all lie in it does too,
  // while every point o + t d of a ray of the beam has n.(t d) >= -(margin - slack) t |d|.
  for (int k = 0; k < planes_; ++k) {
    const glm::dvec3& n = normals_[static_cast<std::size_t>(k)];
    const double margin = margins_[static_cast<std::size_t>(k)];
    bool all = true;
    for (const glm::dvec3& q : points) {
      const glm::dvec3 v = q - origin_;
      if (!(glm::dot(n, v) < -margin * glm::length(v))) {
        all = false;
        break;
      }
    }
    if (all) return true;
  }
  return false;
}

bool Frustum::misses_box(const glm::dvec3& lo, const glm::dvec3& hi) const {
  std::array<glm::dvec3, 8> corners;
  for (std::size_t i = 0; i < 8; ++i) {
    corners[i] = {(i & 1u) ? hi.x : lo.x, (i & 2u) ? hi.y : lo.y, (i & 4u) ? hi.z : lo.z};
  }
  return beyond_a_plane(corners);
}

bool Frustum::misses_triangle(const Triangle& tri) const {
  return beyond_a_plane(std::array<glm::dvec3, 3>{tri.v0, tri.v0 + tri.e1, tri.v0 + tri.e2});
}

std::vector<Hit> trace_primary_beams(const Bvh& bvh, std::span<const Ray> rays, int width, int height, int beam,
                                     BeamCost& cost) {
  if (beam < 1 || beam * beam > kMaxBeamRays) {
    throw Error(fmt::format("a beam of {0}x{0} pixels: the side must be 1..8", beam));
  }
  if (rays.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw Error(fmt::format("{} rays are not the primary rays of a {}x{} image", rays.size(), width, height));
  }
  std::vector<Hit> hits(rays.size());
  std::vector<Ray> tile;
  std::vector<Hit> tile_hits;
  for (int y0 = 0; y0 < height; y0 += beam) {
    for (int x0 = 0; x0 < width; x0 += beam) {
      const int w = std::min(beam, width - x0), h = std::min(beam, height - y0);
      tile.clear();
      for (int y = y0; y < y0 + h; ++y) {
        for (int x = x0; x < x0 + w; ++x) tile.push_back(rays[static_cast<std::size_t>(y) * width + x]);
      }
      const auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * w + x; };
      const Frustum frustum(tile, {at(0, 0), at(w - 1, 0), at(w - 1, h - 1), at(0, h - 1)});
      tile_hits.assign(tile.size(), Hit{});
      bvh.closest_hits_of_beam(tile, frustum, tile_hits, cost);
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) hits[static_cast<std::size_t>(y0 + y) * width + x0 + x] = tile_hits[at(x, y)];
      }
    }
  }
  return hits;
}

}  // namespace rpu::accel
