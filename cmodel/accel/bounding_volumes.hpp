#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/geometry.hpp"
#include "scene/scene.hpp"

namespace rpu::accel {

// Bounding volumes of one object's points (docs/accel.md, "Bounding volumes").

struct Sphere {
  glm::dvec3 centre{0.0};
  double radius = 0.0;
};

// A box of three orthonormal axes (the columns of `axes`) about `centre`, `half` its
// half extents along them.
struct OrientedBox {
  glm::dvec3 centre{0.0};
  glm::dmat3 axes{1.0};
  glm::dvec3 half{0.0};
};

double volume(const Bounds& box);
double volume(const Sphere& sphere);
double volume(const OrientedBox& box);

// Ritter's sphere (Ritter 1990, "An efficient bounding sphere", Graphics Gems): from the
// first point the farthest point y, from y the farthest z; the sphere on the diameter yz;
// then one pass that grows it to just reach each point outside. A last pass raises the
// radius to the largest distance from the centre, so rounding in the growth steps never
// leaves a point outside. No points: radius 0 at the origin.
Sphere ritter_sphere(std::span<const glm::dvec3> points);

// The box along the principal axes of the points (the eigenvectors of their covariance,
// by Jacobi rotations; Gottschalk, Lin and Manocha 1996 take a mesh's covariance the
// same way), just wide enough for every point.
OrientedBox pca_box(std::span<const glm::dvec3> points);

// The eigenvectors (columns) of a symmetric 3x3 matrix by cyclic Jacobi rotations,
// orthonormal; `values` gets the eigenvalues.
glm::dmat3 symmetric_eigenvectors(const glm::dmat3& m, glm::dvec3& values);

// The scene's objects: the classes of triangles that share a vertex position (directly
// or through others), each as the distinct positions of its vertices, in the order of
// each class's first triangle. Triangles rpu::accel::TriangleSet skips (an index out of
// range, a vertex not finite, degenerate) belong to none.
std::vector<std::vector<glm::dvec3>> scene_objects(const Scene& scene);

}  // namespace rpu::accel
