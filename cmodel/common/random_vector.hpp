#pragma once

#include <glm/vec3.hpp>

namespace rpu {

// A vector of three draws from `dist`, made in a fixed order: z, then y, then x. C++
// leaves the order of a call's arguments to the compiler (gcc evaluates them right to
// left, clang left to right), so glm::dvec3(d(rng), d(rng), d(rng)) is another vector
// under another compiler. z first keeps the vectors gcc made, on which the tests' random
// inputs and thresholds were chosen.
template <class Vector = glm::dvec3, class Distribution, class Engine>
Vector random_vector(Distribution& dist, Engine& rng) {
  const auto z = dist(rng);
  const auto y = dist(rng);
  const auto x = dist(rng);
  return Vector(x, y, z);
}

}  // namespace rpu
