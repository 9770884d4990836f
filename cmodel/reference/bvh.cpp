#include "reference/bvh.hpp"

#include <algorithm>
#include <cmath>

namespace rpu {

namespace {
constexpr std::uint32_t kMaxLeafTriangles = 4;
// A median split halves the triangle count, so depth <= log2(2^32) + 1 fits.
constexpr int kStackDepth = 64;

// Moeller-Trumbore in double precision. Degenerate triangles never reach here (the
// scene loader drops them), but det == 0 is still a miss, never a division by zero.
bool intersect(const Ray& ray, const glm::dvec3& v0, const glm::dvec3& e1, const glm::dvec3& e2,
               double t_max, double& t, double& u, double& v) {
  const glm::dvec3 p = glm::cross(ray.direction, e2);
  const double det = glm::dot(e1, p);
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const glm::dvec3 s = ray.origin - v0;
  u = glm::dot(s, p) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const glm::dvec3 q = glm::cross(s, e1);
  v = glm::dot(ray.direction, q) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  t = glm::dot(e2, q) * inv;
  return t > ray.t_min && t < t_max;
}

// Slab test. A zero direction component gets a huge finite reciprocal instead of inf,
// so an origin exactly on a slab plane gives 0 * big = 0, never 0 * inf = NaN.
bool hits_box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& origin, const glm::dvec3& inv_dir,
              double t_min, double t_max) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (lo[a] - origin[a]) * inv_dir[a];
    double t1 = (hi[a] - origin[a]) * inv_dir[a];
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
  }
  return t_min <= t_max;
}
}  // namespace

ReferenceBvh::ReferenceBvh(const Scene& scene) {
  const std::size_t n = scene.triangles.size();
  triangles_.resize(n);
  order_.resize(n);
  std::vector<glm::dvec3> centroids(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::uvec3 t = scene.triangles[i];
    const glm::dvec3 a(scene.positions[t.x]), b(scene.positions[t.y]), c(scene.positions[t.z]);
    triangles_[i] = {a, b - a, c - a};
    centroids[i] = (a + b + c) / 3.0;
    order_[i] = static_cast<std::uint32_t>(i);
  }
  nodes_.reserve(2 * n / kMaxLeafTriangles + 1);
  if (n > 0) build(0, static_cast<std::uint32_t>(n), centroids);
  // Store triangles in leaf order so a leaf reads them sequentially.
  std::vector<Triangle> in_scene_order = std::move(triangles_);
  triangles_.resize(n);
  for (std::size_t i = 0; i < n; ++i) triangles_[i] = in_scene_order[order_[i]];
}

std::uint32_t ReferenceBvh::build(std::uint32_t begin, std::uint32_t end, std::vector<glm::dvec3>& centroids) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  constexpr double kInf = std::numeric_limits<double>::infinity();
  glm::dvec3 lo(kInf), hi(-kInf), clo(kInf), chi(-kInf);
  for (std::uint32_t i = begin; i < end; ++i) {
    const Triangle& t = triangles_[order_[i]];
    for (const glm::dvec3& p : {t.v0, t.v0 + t.e1, t.v0 + t.e2}) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    clo = glm::min(clo, centroids[order_[i]]);
    chi = glm::max(chi, centroids[order_[i]]);
  }
  nodes_[index] = {lo, hi, begin, end - begin};
  const glm::dvec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  if (end - begin <= kMaxLeafTriangles || extent[axis] <= 0.0) return index;
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  build(begin, mid, centroids);
  const std::uint32_t right = build(mid, end, centroids);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

template <bool kAnyHit>
Hit ReferenceBvh::traverse(const Ray& ray) const {
  Hit best;
  if (nodes_.empty()) return best;
  glm::dvec3 inv_dir;
  for (int a = 0; a < 3; ++a) {
    inv_dir[a] = ray.direction[a] != 0.0 ? 1.0 / ray.direction[a] : std::copysign(1e300, ray.direction[a]);
  }
  double t_max = ray.t_max;
  std::uint32_t stack[kStackDepth];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!hits_box(node.lo, node.hi, ray.origin, inv_dir, ray.t_min, t_max)) continue;
    if (node.count == 0) {
      const auto self = static_cast<std::uint32_t>(&node - nodes_.data());
      stack[top++] = node.first;
      stack[top++] = self + 1;
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const Triangle& tri = triangles_[i];
      double t, u, v;
      if (!intersect(ray, tri.v0, tri.e1, tri.e2, t_max, t, u, v)) continue;
      best = {t, order_[i], u, v};
      if constexpr (kAnyHit) return best;
      t_max = t;
    }
  }
  return best;
}

Hit ReferenceBvh::closest_hit(const Ray& ray) const { return traverse<false>(ray); }
bool ReferenceBvh::any_hit(const Ray& ray) const { return traverse<true>(ray).hit(); }

}  // namespace rpu
