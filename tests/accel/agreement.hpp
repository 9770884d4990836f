#pragma once

// Every structure against brute force on one scene's primary, random and shadow rays.
#include <functional>
#include <string>

#include "scene/scene.hpp"

namespace rpu::accel::test {

struct AgreementCase {
  std::string name;  // the test's name
  std::function<Scene()> scene;
  int width, height;  // primary rays, and shadow rays from their hits
  int random;         // random rays
  std::size_t min_rays;  // all rays at least (the claim the test holds)
};

// The scenes: built-in names and files through resolve_scene.
Scene scene_named(const std::string& name);

// Runs the case: for each structure but brute force, closest hits (primitive and t)
// identical to brute force's, and any hit answers equal to whether brute force hit.
void expect_agreement(const AgreementCase& c);

}  // namespace rpu::accel::test
