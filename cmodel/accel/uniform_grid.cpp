#include "accel/uniform_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "accel/box.hpp"
#include "accel/triangle_box.hpp"
#include "common/error.hpp"

namespace rpu::accel {

namespace {
// An axis shorter than this fraction of the longest is flat: one cell thick.
constexpr double kFlatFraction = 1e-6;

// In double: three axes of up to kMaxCells cells each overflow 64 bits.
double cell_count(const glm::ivec3& r) { return double(r.x) * double(r.y) * double(r.z); }
}  // namespace

UniformGrid::UniformGrid(const TriangleSet& set, double lambda, bool mailbox)
    : triangles_(set.triangles()), lambda_(lambda), mailbox_(mailbox) {
  if (!(lambda > 0.0 && lambda <= 1e6)) {
    throw Error(fmt::format("grid lambda {} is not a number of cells per triangle in (0, 1e6]; try 4", lambda));
  }
  if (triangles_.empty()) return;

  // Resolution: cells of one size on every non-flat axis, about lambda * N of them.
  const Bounds& b = set.bounds();
  const glm::dvec3 extent = b.hi - b.lo;
  const double longest = std::max({extent.x, extent.y, extent.z});
  double measure = 1.0;
  int dimensions = 0;
  for (int a = 0; a < 3; ++a) {
    if (extent[a] > kFlatFraction * longest) {
      measure *= extent[a];
      ++dimensions;
    }
  }
  double density = std::pow(lambda * static_cast<double>(triangles_.size()) / measure, 1.0 / dimensions);
  auto resolution_at = [&](double cells_per_unit) {
    glm::ivec3 r(1);
    for (int a = 0; a < 3; ++a) {
      if (extent[a] > kFlatFraction * longest) {
        r[a] = static_cast<int>(std::clamp(std::round(extent[a] * cells_per_unit), 1.0, double(kMaxCells)));
      }
    }
    return r;
  };
  resolution_ = resolution_at(density);
  while (cell_count(resolution_) > double(kMaxCells)) {
    density *= 0.95;
    resolution_ = resolution_at(density);
  }

  const double pad = box_pad(b);
  lo_ = b.lo - pad;
  hi_ = b.hi + pad;
  cell_size_ = (hi_ - lo_) / glm::dvec3(resolution_);
  if (mailbox_) tested_by_ray_.assign(triangles_.size(), 0);

  // Bin each triangle into the cells its padded box reaches and the separating-axis
  // test keeps; then a counting sort by cell, stable, so references ascend in a cell.
  const auto cells = static_cast<std::uint64_t>(cell_count(resolution_));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_and_triangle;
  cell_and_triangle.reserve(triangles_.size() * 2);
  auto cell_of = [&](double x, int a) {
    return static_cast<int>(std::clamp(std::floor((x - lo_[a]) / cell_size_[a]), 0.0, double(resolution_[a] - 1)));
  };
  for (std::uint32_t k = 0; k < triangles_.size(); ++k) {
    const Triangle& t = triangles_[k];
    const glm::dvec3 v1 = t.v0 + t.e1, v2 = t.v0 + t.e2;
    const glm::dvec3 t_lo = glm::min(t.v0, glm::min(v1, v2)) - pad, t_hi = glm::max(t.v0, glm::max(v1, v2)) + pad;
    glm::ivec3 first, last;
    for (int a = 0; a < 3; ++a) {
      first[a] = cell_of(t_lo[a], a);
      last[a] = cell_of(t_hi[a], a);
    }
    const bool one_cell = first == last;
    for (int z = first.z; z <= last.z; ++z) {
      for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) {
          const glm::dvec3 cell_lo = lo_ + glm::dvec3(x, y, z) * cell_size_;
          const glm::dvec3 cell_hi = lo_ + glm::dvec3(x + 1, y + 1, z + 1) * cell_size_;
          if (!one_cell && !triangle_overlaps_box(t.v0, v1, v2, cell_lo - pad, cell_hi + pad)) continue;
          const auto cell = static_cast<std::uint32_t>((static_cast<std::uint64_t>(z) * resolution_.y + y) *
                                                           resolution_.x + x);
          cell_and_triangle.emplace_back(cell, k);
        }
      }
    }
  }
  if (cell_and_triangle.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(fmt::format("grid with lambda {} needs {} references, more than 32-bit offsets hold; lower "
                            "--grid-lambda", lambda, cell_and_triangle.size()));
  }
  cell_begin_.assign(cells + 1, 0);
  for (const auto& [cell, k] : cell_and_triangle) ++cell_begin_[cell + 1];
  for (std::uint64_t c = 0; c < cells; ++c) cell_begin_[c + 1] += cell_begin_[c];
  references_.resize(cell_and_triangle.size());
  std::vector<std::uint32_t> fill(cell_begin_.begin(), cell_begin_.end() - 1);
  for (const auto& [cell, k] : cell_and_triangle) references_[fill[cell]++] = k;
}

std::string UniformGrid::parameters() const {
  return fmt::format("{}x{}x{} cells, lambda {}, {:.2f} refs/triangle{}", resolution_.x, resolution_.y,
                     resolution_.z, lambda_,
                     triangles_.empty() ? 0.0 : double(references_.size()) / double(triangles_.size()),
                     mailbox_ ? ", mailboxes" : "");
}

std::uint64_t UniformGrid::memory_bytes() const {
  // A cell's record is one 32-bit offset (4 bytes stored; a visit reads its own and the next).
  return stored_bytes(cell_begin_.size(), sizeof(std::uint32_t), references_.size(), triangles_.size());
}

Hit UniformGrid::closest_hit(const Ray& ray, RayCost& cost) const { return walk<false>(ray, cost); }

bool UniformGrid::any_hit(const Ray& ray, RayCost& cost) const { return walk<true>(ray, cost).hit(); }

template <bool kAnyHit>
Hit UniformGrid::walk(const Ray& ray, RayCost& cost) const {
  Hit best;
  if (references_.empty()) return best;
  const RootSegment root = enter_root(lo_, hi_, ray);
  if (!root.entered) return best;
  const glm::dvec3& inv = root.inv;
  const double t_enter = root.t_near, t_end = root.t_far;
  const std::uint64_t ray_number = ++ray_number_;

  // The DDA's set-up: the entry cell, and per axis the step, the t of the next boundary
  // and the t from one boundary to the next.
  const glm::dvec3 entry = ray.origin + t_enter * ray.direction;
  glm::ivec3 cell, step(0), outside(0);
  glm::dvec3 t_next(std::numeric_limits<double>::infinity()), dt(0.0);
  for (int a = 0; a < 3; ++a) {
    cell[a] = static_cast<int>(
        std::clamp(std::floor((entry[a] - lo_[a]) / cell_size_[a]), 0.0, double(resolution_[a] - 1)));
    if (ray.direction[a] > 0.0) {
      step[a] = 1;
      outside[a] = resolution_[a];
      t_next[a] = (lo_[a] + (cell[a] + 1) * cell_size_[a] - ray.origin[a]) * inv[a];
      dt[a] = cell_size_[a] * inv[a];
    } else if (ray.direction[a] < 0.0) {
      step[a] = -1;
      outside[a] = -1;
      t_next[a] = (lo_[a] + cell[a] * cell_size_[a] - ray.origin[a]) * inv[a];
      dt[a] = -cell_size_[a] * inv[a];
    }
  }

  for (;;) {
    const std::uint64_t c = (static_cast<std::uint64_t>(cell.z) * resolution_.y + cell.y) * resolution_.x + cell.x;
    ++cost.nodes;
    cost.bytes += kCellRecordBytes;
    const auto cell_references =
        std::span(references_).subspan(cell_begin_[c], cell_begin_[c + 1] - cell_begin_[c]);
    if (test_references<kAnyHit>(ray, triangles_, cell_references, best, cost, [&](std::uint32_t k) {
          if (!mailbox_) return true;
          if (tested_by_ray_[k] == ray_number) return false;
          tested_by_ray_[k] = ray_number;
          return true;
        })) {
      return best;
    }
    // The cell ends where the first axis crosses its next boundary. A hit found so far
    // is final only if it lies within the cells walked: a triangle reaching into later
    // cells may have been hit beyond this one, where a nearer triangle may still wait
    // (the classic pitfall). The hit is kept, not dropped: with mailboxes the triangle
    // would not be tested again in the cell its hit lies in.
    const int axis = t_next.x < t_next.y ? (t_next.x < t_next.z ? 0 : 2) : (t_next.y < t_next.z ? 1 : 2);
    const double t_exit = t_next[axis];
    if (best.t <= t_exit || t_exit >= t_end) break;
    cell[axis] += step[axis];
    if (cell[axis] == outside[axis]) break;
    t_next[axis] += dt[axis];
  }
  return best;
}

}  // namespace rpu::accel
