#include "accel/structure.hpp"

#include <fmt/format.h>

#include "accel/brute_force.hpp"
#include "accel/bsp.hpp"
#include "accel/bvh.hpp"
#include "accel/kd_tree.hpp"
#include "accel/octree.hpp"
#include "accel/uniform_grid.hpp"
#include "common/error.hpp"

namespace rpu::accel {

std::vector<std::string> structure_names() { return {"brute", "grid", "octree", "octree-r", "bsp", "bvh", "kdtree"}; }

std::unique_ptr<Structure> build_structure(std::string_view name, const TriangleSet& triangles,
                                           const StructureOptions& options) {
  if (name == "brute") return std::make_unique<BruteForce>(triangles);
  if (name == "grid") return std::make_unique<UniformGrid>(triangles, options.grid_lambda, options.grid_mailbox);
  if (name == "octree") return std::make_unique<Octree>(triangles, OctreeSplit::kMidpoint);
  if (name == "octree-r") return std::make_unique<Octree>(triangles, OctreeSplit::kCost);
  if (name == "bsp") return std::make_unique<Bsp>(triangles);
  if (name == "bvh") return std::make_unique<Bvh>(triangles);
  if (name == "kdtree") return std::make_unique<KdTreeStructure>(triangles);
  throw Error(fmt::format("unknown acceleration structure '{}'; known: {}", name,
                          fmt::join(structure_names(), ", ")));
}

}  // namespace rpu::accel
