#pragma once

#include <cstdint>

#include "scene/ray.hpp"

namespace rpu::accel {

// What one ray cost a structure. nodes: nodes (grid cells) whose record was read;
// tests: ray/triangle tests; bytes: every byte read from the structure's memory, by the
// byte model each structure states (docs/accel.md, "Byte model").
struct RayCost {
  std::uint64_t nodes = 0;
  std::uint64_t tests = 0;
  std::uint64_t bytes = 0;

  RayCost& operator+=(const RayCost& o) {
    nodes += o.nodes;
    tests += o.tests;
    bytes += o.bytes;
    return *this;
  }
};

}  // namespace rpu::accel
