#pragma once

// A small scene and hand-made kd-trees over it for memory-image tests and fuzz seeds.
// The trees are valid images of the layout rules, not SAH-built trees: the builder
// lives elsewhere, and the image must take any tree that follows the rules.
#include <cstdint>
#include <numeric>

#include "kdtree/kdtree.hpp"
#include "scene/scene.hpp"

namespace rpu::test {

// Four non-axis-aligned triangles over six shared vertices, with normals and uvs, two
// materials on two shaders plus a third sharing the first shader, one light of each
// kind and a thin-lens camera.
inline Scene tiny_scene() {
  Scene s;
  s.source = "tiny";
  s.positions = {{0.0f, 0.0f, 0.0f},  {1.0f, 0.1f, 0.2f},   {0.2f, 1.0f, -0.3f},
                 {1.5f, 1.2f, 0.7f},  {-0.7f, 0.4f, 1.1f},  {0.3f, -0.9f, 2.5f}};
  s.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0.6f, 0.8f, 0}, {0, 0.6f, 0.8f}, {0.8f, 0, 0.6f}};
  s.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.5f, 0.25f}, {0.75f, 0.5f}};
  s.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 2, 4}, {0, 5, 1}};
  s.material_ids = {0, 1, 2, 0};
  Material a;
  a.name = "clay";
  a.ambient = {0.1, 0.2, 0.3};
  a.diffuse = {0.4, 0.5, 0.6};
  a.specular = {0.7, 0.8, 0.9};
  a.shininess = 20.0;
  a.reflectance = 0.25;
  a.transmittance = 0.125;
  a.ior = 1.5;
  Material b = a;
  b.name = "mirror";
  b.shader = "mirror";
  b.reflectance = 0.9;
  b.roughness = 0.125;
  Material c = a;
  c.name = "glass";
  c.ior = 1.33;
  s.materials = {a, b, c};
  Light point;
  point.kind = LightKind::kPoint;
  point.color = {0.5, 0.6, 0.7};
  point.position = {1.0, 2.0, 3.0};
  Light sun;
  sun.kind = LightKind::kDirectional;
  sun.direction = {0.0, -0.6, -0.8};
  Light area;
  area.kind = LightKind::kArea;
  area.position = {-1.0, 4.0, -1.0};
  area.edge_u = {2.0, 0.0, 0.0};
  area.edge_v = {0.0, 0.0, 2.0};
  s.lights = {point, sun, area};
  s.camera.position = {3.0, 2.0, 6.0};
  s.camera.look_at = {0.25, 0.25, 0.5};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.vfov_degrees = 35.0;
  s.camera.aperture_radius = 0.05;
  s.camera.focus_distance = 6.5;
  s.background = {0.05, 0.1, 0.2};
  return s;
}

inline void set_root_box(KdTree& t) {
  t.bounds_lo = {-0.7f, -0.9f, -0.3f};
  t.bounds_hi = {1.5f, 1.2f, 2.5f};
}

// One leaf holding every triangle.
inline KdTree single_leaf_tree(std::uint32_t triangles) {
  KdTree t;
  t.nodes = {KdNode::leaf(triangles, 0)};
  t.prim_refs.resize(triangles);
  std::iota(t.prim_refs.begin(), t.prim_refs.end(), 0u);
  set_root_box(t);
  return t;
}

// Node 0 splits x at 0.5: below leaf 1 = {0, 2, 3, 1}; above inner node 2 splits y at
// 0.25: below leaf 3 = {1, 3}, above leaf 4 empty. Five nodes, six prim refs.
inline KdTree split_tree() {
  KdTree t;
  t.nodes = {KdNode::inner(0, 2, 0.5f), KdNode::leaf(4, 0), KdNode::inner(1, 4, 0.25f), KdNode::leaf(2, 4),
             KdNode::leaf(0, 6)};
  t.prim_refs = {0, 2, 3, 1, 1, 3};
  set_root_box(t);
  return t;
}

}  // namespace rpu::test
