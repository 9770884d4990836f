#include "accel/bounding_volumes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <unordered_map>

namespace rpu::accel {

double volume(const Bounds& box) {
  if (box.empty()) return 0.0;
  const glm::dvec3 e = box.hi - box.lo;
  return e.x * e.y * e.z;
}

double volume(const Sphere& sphere) { return 4.0 / 3.0 * std::numbers::pi * std::pow(sphere.radius, 3); }

double volume(const OrientedBox& box) { return 8.0 * box.half.x * box.half.y * box.half.z; }

Sphere ritter_sphere(std::span<const glm::dvec3> points) {
  if (points.empty()) return {};
  auto farthest_from = [&](const glm::dvec3& from) {
    return *std::max_element(points.begin(), points.end(), [&](const glm::dvec3& a, const glm::dvec3& b) {
      return glm::length(a - from) < glm::length(b - from);
    });
  };
  const glm::dvec3 y = farthest_from(points.front());
  const glm::dvec3 z = farthest_from(y);
  Sphere s{0.5 * (y + z), 0.5 * glm::length(z - y)};
  for (const glm::dvec3& p : points) {
    const double d = glm::length(p - s.centre);
    if (d <= s.radius) continue;
    // The sphere through p and the far side of the old one: its diameter r + d.
    const double radius = 0.5 * (s.radius + d);
    s.centre += (d - radius) / d * (p - s.centre);
    s.radius = radius;
  }
  for (const glm::dvec3& p : points) s.radius = std::max(s.radius, glm::length(p - s.centre));
  return s;
}

glm::dmat3 symmetric_eigenvectors(const glm::dmat3& m, glm::dvec3& values) {
  double a[3][3], v[3][3];  // a[row][column]; v's columns become the eigenvectors
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      a[r][c] = m[c][r];
      v[r][c] = r == c ? 1.0 : 0.0;
    }
  }
  // Cyclic Jacobi: each rotation in the (p, q) plane zeroes a[p][q] (Golub and Van Loan,
  // "Matrix Computations", 8.5); a 3x3 matrix converges in a few sweeps.
  constexpr int kSweeps = 50;
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diagonal = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (!(off > 1e-32 * diagonal)) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {
          const double kp = a[k][p], kq = a[k][q];
          a[k][p] = c * kp - s * kq;
          a[k][q] = s * kp + c * kq;
        }
        for (int k = 0; k < 3; ++k) {
          const double pk = a[p][k], qk = a[q][k];
          a[p][k] = c * pk - s * qk;
          a[q][k] = s * pk + c * qk;
        }
        for (int k = 0; k < 3; ++k) {
          const double kp = v[k][p], kq = v[k][q];
          v[k][p] = c * kp - s * kq;
          v[k][q] = s * kp + c * kq;
        }
      }
    }
  }
  glm::dmat3 vectors;
  for (int c = 0; c < 3; ++c) {
    values[c] = a[c][c];
    for (int r = 0; r < 3; ++r) vectors[c][r] = v[r][c];
  }
  return vectors;
}

OrientedBox pca_box(std::span<const glm::dvec3> points) {
  OrientedBox box;
  if (points.empty()) return box;
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : points) mean += p;
  mean /= double(points.size());
  glm::dmat3 covariance(0.0);
  for (const glm::dvec3& p : points) covariance += glm::outerProduct(p - mean, p - mean);
  glm::dvec3 values;
  box.axes = symmetric_eigenvectors(covariance, values);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : points) {
    const glm::dvec3 along = glm::transpose(box.axes) * (p - mean);
    lo = glm::min(lo, along);
    hi = glm::max(hi, along);
  }
  box.centre = mean + box.axes * (0.5 * (lo + hi));
  box.half = 0.5 * (hi - lo);
  return box;
}

std::vector<std::vector<glm::dvec3>> scene_objects(const Scene& scene) {
  // A position's key: its three coordinates' bits, -0 made +0.
  struct Key {
    std::uint32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return (std::size_t{k.x} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k.y} * 0xC2B2AE3D27D4EB4Full) ^ k.z;
    }
  };
  auto key_of = [](const glm::vec3& p) {
    return Key{std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
               std::bit_cast<std::uint32_t>(p.z + 0.0f)};
  };
  const std::size_t n = scene.triangles.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto root = [&](std::size_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  std::vector<char> kept(n, 0);
  std::unordered_map<Key, std::size_t, KeyHash> first_with;  // position -> a triangle using it
  for (std::size_t t = 0; t < n; ++t) {
    const glm::uvec3 idx = scene.triangles[t];
    const std::size_t count = scene.positions.size();
    if (idx.x >= count || idx.y >= count || idx.z >= count) continue;
    const glm::vec3 v[3] = {scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z]};
    bool finite = true;
    for (const glm::vec3& p : v) finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    if (!finite || is_degenerate(v[0], v[1], v[2])) continue;
    kept[t] = 1;
    for (const glm::vec3& p : v) {
      const auto [at, inserted] = first_with.try_emplace(key_of(p), t);
      if (!inserted) parent[root(t)] = root(at->second);
    }
  }
  std::vector<std::vector<glm::dvec3>> objects;
  std::unordered_map<std::size_t, std::size_t> object_of_root;
  std::unordered_map<Key, char, KeyHash> placed;
  for (std::size_t t = 0; t < n; ++t) {
    if (!kept[t]) continue;
    const auto [at, inserted] = object_of_root.try_emplace(root(t), objects.size());
    if (inserted) objects.emplace_back();
    const glm::uvec3 idx = scene.triangles[t];
    for (const std::uint32_t i : {idx.x, idx.y, idx.z}) {
      if (placed.try_emplace(key_of(scene.positions[i]), 1).second) objects[at->second].emplace_back(scene.positions[i]);
    }
  }
  return objects;
}

}  // namespace rpu::accel
