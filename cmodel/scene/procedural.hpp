#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.hpp"

namespace rpu {

// The Cornell box from Cornell's published measurements (mm, y up): walls, the two
// blocks (the tall one a mirror), a glass sphere on the short block and a rectangular
// area light at the ceiling lamp. The default scene. `sphere_slices` tessellates the
// glass sphere (see make_sphereflake).
Scene make_cornell_box(int sphere_slices = 32);

// Eric Haines' SPD "balls" (sphereflake): a sphere of radius 0.5 at the origin, and
// recursively 9 children of 1/3 the radius on each sphere, `levels` deep (SPD's
// size factor), on a square floor, with SPD's camera, three lights and materials.
// Each sphere is a UV sphere of `slices` columns and slices/2 rows:
// slices*(slices-2) triangles (slices even, 4..1024).
Scene make_sphereflake(int levels = 3, int slices = 16);

// Eric Haines' SPD "tetra": a Sierpinski tetrahedron of 4^levels triangles (levels >= 1)
// with SPD's camera and light.
Scene make_tetra(int levels = 6);

// A teapot in a stadium (Haines' term for the case that defeats a uniform grid): the
// tetra of `levels` (within [-1, 1]^3, SPD's light) inside a cube 2000 wide, 12 large
// triangles, seen from (0, 0.5, 4).
Scene make_stadium(int levels = 6);

// `count` small triangles scattered uniformly over the unit cube: each vertex within
// +-0.04 (3000 / count)^(1/3) of its triangle's centre on each axis (so the scene keeps
// its character at every count), from std::mt19937(5); a camera at (0.5, 0.6, 3) and a
// point light at (2, 3, 2). count 1..kMaxScattered.
inline constexpr int kMaxScattered = 1000000;
Scene make_scattered(int count = 3000);

// The built-in generators by name, each optionally followed by ":size"
// ("cornell", "balls:4", "tetra:3", "stadium", "scattered:100000"). Throws rpu::Error for an unknown name or a bad size.
Scene make_builtin_scene(std::string_view name_and_size);

// Generator names accepted by make_builtin_scene, in a stable order.
std::vector<std::string> builtin_scene_names();

// True when `name_and_size` names a built-in generator (the size is not checked).
bool is_builtin_scene(std::string_view name_and_size);

}  // namespace rpu
