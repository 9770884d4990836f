#include "accel/triangles.hpp"

#include <cmath>

namespace rpu::accel {

TriangleSet::TriangleSet(const Scene& scene) {
  triangles_.reserve(scene.triangles.size());
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const glm::uvec3 idx = scene.triangles[i];
    const std::size_t n = scene.positions.size();
    if (idx.x >= n || idx.y >= n || idx.z >= n) {
      ++skipped_;
      continue;
    }
    const glm::vec3 a = scene.positions[idx.x], b = scene.positions[idx.y], c = scene.positions[idx.z];
    bool finite = true;
    for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(a[k]) && std::isfinite(b[k]) && std::isfinite(c[k]);
    if (!finite || is_degenerate(a, b, c)) {
      ++skipped_;
      continue;
    }
    const glm::dvec3 da(a), db(b), dc(c);
    triangles_.push_back({da, db - da, dc - da, static_cast<std::uint32_t>(i)});
    bounds_.extend(da);
    bounds_.extend(db);
    bounds_.extend(dc);
  }
}

}  // namespace rpu::accel
