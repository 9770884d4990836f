#include "accel/minimum_sphere.hpp"

#include <vector>

#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <CGAL/Simple_cartesian.h>

namespace rpu::accel {

Sphere minimum_sphere(std::span<const glm::dvec3> points) {
  if (points.empty()) return {};
  using Kernel = CGAL::Simple_cartesian<double>;
  using Traits = CGAL::Min_sphere_of_spheres_d_traits_3<Kernel, double>;
  std::vector<Traits::Sphere> spheres;
  spheres.reserve(points.size());
  for (const glm::dvec3& p : points) spheres.emplace_back(Kernel::Point_3(p.x, p.y, p.z), 0.0);
  // Not const: CGAL computes the sphere lazily in radius() and center_cartesian_begin().
  CGAL::Min_sphere_of_spheres_d<Traits> smallest(spheres.begin(), spheres.end());
  Sphere s;
  auto c = smallest.center_cartesian_begin();
  for (int a = 0; a < 3; ++a, ++c) s.centre[a] = *c;
  s.radius = smallest.radius();
  return s;
}

}  // namespace rpu::accel
