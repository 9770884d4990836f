#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "fp/format.hpp"
#include "memory/memory_image.hpp"

// The Yosys cell counts of bench/results/area.json (docs/area.md), built into the tool:
// what a sweep point records as the area of its number format and intersection test.
namespace rpu::sweep {

// The datapath of one ray-tracing core in a format: the FP units (fma, misc, divsqrt),
// the intersection unit (micro-program) and the traversal unit (one ray slot), the
// latest synthesis of each. None when one of them was not synthesised in that format.
std::optional<std::uint64_t> datapath_cells(fp::Format format, IsectMode mode);

// The whole chip of a named configuration (its format), when it was synthesised.
std::optional<std::uint64_t> chip_cells(std::string_view config, IsectMode mode);

}  // namespace rpu::sweep
