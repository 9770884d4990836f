#include "accel/brute_force.hpp"

namespace rpu::accel {

Hit BruteForce::closest_hit(const Ray& ray, RayCost& cost) const {
  Hit best;
  test_triangles<false>(ray, triangles_, best, cost);
  return best;
}

bool BruteForce::any_hit(const Ray& ray, RayCost& cost) const {
  Hit best;
  return test_triangles<true>(ray, triangles_, best, cost);
}

}  // namespace rpu::accel
