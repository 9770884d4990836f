#include "accel/brute_force.hpp"

namespace rpu::accel {

Hit BruteForce::closest_hit(const Ray& ray, RayCost& cost) const {
  Hit best;
  for (const Triangle& tri : triangles_) {
    double t;
    if (intersect(ray, tri, t) && best.improved_by(t, tri.prim)) best = {t, tri.prim};
  }
  cost.tests += triangles_.size();
  cost.bytes += triangles_.size() * kTriangleRecordBytes;
  return best;
}

bool BruteForce::any_hit(const Ray& ray, RayCost& cost) const {
  for (const Triangle& tri : triangles_) {
    ++cost.tests;
    cost.bytes += kTriangleRecordBytes;
    double t;
    if (intersect(ray, tri, t)) return true;
  }
  return false;
}

}  // namespace rpu::accel
