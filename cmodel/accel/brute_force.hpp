#pragma once

#include <vector>

#include "accel/structure.hpp"

namespace rpu::accel {

// Every ray tests every triangle: the baseline the structures are measured against and
// the oracle they are tested against. Byte model: one triangle record per test; there
// are no nodes and no references.
class BruteForce final : public Structure {
 public:
  explicit BruteForce(const TriangleSet& triangles) : triangles_(triangles.triangles()) {}

  std::string_view name() const override { return "brute"; }
  std::string parameters() const override { return "no structure"; }
  Hit closest_hit(const Ray& ray, RayCost& cost) const override;
  bool any_hit(const Ray& ray, RayCost& cost) const override;
  std::uint64_t memory_bytes() const override { return stored_bytes(0, 0, 0, triangles_.size()); }
  std::uint64_t node_count() const override { return 0; }

 private:
  std::vector<Triangle> triangles_;
};

}  // namespace rpu::accel
