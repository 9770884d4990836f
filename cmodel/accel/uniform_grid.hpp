#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "accel/structure.hpp"

namespace rpu::accel {

// A uniform grid walked by the 3D-DDA of Amanatides and Woo 1987: per axis the t of
// the next cell boundary (tnext) and the t between boundaries (dt), stepping the axis
// whose boundary comes first.
//
// Resolution: about lambda * N cells, the same cell size on every axis, so an axis gets
// extent * cbrt(lambda N / V) cells (Cleary and Wyvill 1988; Ize et al. 2007 measure
// lambda between 2 and 8 as good). A flat axis (extent below 1e-6 of the largest) gets
// one cell and the density is taken over the other axes.
//
// Storage and byte model: a cell is a range in one reference array (the offsets of
// cell c and c + 1, 8 bytes read per cell visited, 4 stored per cell); a reference is a
// 32-bit triangle index (4 bytes); a triangle test reads its 36-byte record.
// Mailboxing reads the reference but skips the test and its record.
class UniformGrid final : public Structure {
 public:
  // Cells more than this are not made, whatever lambda asks: 128 MB of offsets.
  static constexpr std::uint64_t kMaxCells = std::uint64_t{1} << 25;
  static constexpr std::uint64_t kCellRecordBytes = 8;

  UniformGrid(const TriangleSet& triangles, double lambda, bool mailbox);

  std::string_view name() const override { return "grid"; }
  std::string parameters() const override;
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override;
  std::uint64_t node_count() const override { return cell_begin_.empty() ? 0 : cell_begin_.size() - 1; }

  glm::ivec3 resolution() const { return resolution_; }
  std::uint64_t reference_count() const { return references_.size(); }

 private:
  template <bool kAnyHit>
  Hit walk(const Ray& ray, RayCost& cost) const;

  std::vector<Triangle> triangles_;
  double lambda_;
  bool mailbox_;
  glm::dvec3 lo_{0.0}, hi_{0.0}, cell_size_{1.0};
  glm::ivec3 resolution_{0};
  std::vector<std::uint32_t> cell_begin_;  // cell c holds references_[cell_begin_[c], cell_begin_[c + 1])
  std::vector<std::uint32_t> references_;  // indices into triangles_, increasing within a cell
  // Mailboxes (Amanatides and Woo 1987): the ray that last tested each triangle. Scratch
  // of the single-threaded walk, not part of the structure.
  mutable std::vector<std::uint64_t> tested_by_ray_;
  mutable std::uint64_t ray_number_ = 0;
};

}  // namespace rpu::accel
