// The traversal units' timing alone (cycle/ray_unit_timing.hpp, cycle/tu_pipe_timing.hpp),
// built from named configurations.
#include <gtest/gtest.h>

#include "common/hardware_config.hpp"
#include "cycle/tu_pipe_timing.hpp"

namespace rpu::cycle {
namespace {

// rpu_top's cache arbiter keeps log2(units) of the cache's 4 tag bits for itself, and a
// unit's in-order port holds as many lines as the rest name (docs/cycle-model.md): 16
// with one traversal unit (rpu2005), 4 with four (drpu).
TEST(PipeCosts, ThePortHoldsTheLinesTheUnitsTagBitsName) {
  EXPECT_EQ(PipeCosts::of(hardware_config("rpu2005"), IsectMode::kWoop).port_lines, 16u);
  EXPECT_EQ(PipeCosts::of(hardware_config("drpu"), IsectMode::kWoop).port_lines, 4u);
}

}  // namespace
}  // namespace rpu::cycle
