#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "fp/format.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

// The Yosys cell counts of bench/results/area.json (docs/area.md), read when first asked
// for (RPU_AREA_RECORDS names another file; rpu::Error naming the file if it cannot be
// read): what a sweep point records as the area of its number format and intersection test.
namespace rpu::sweep {

// The datapath of one ray-tracing core in a format: the FP units (fma, misc, divsqrt),
// the intersection unit (micro-program) and the traversal unit (one ray slot), the
// latest synthesis of each. None when one of them was not synthesised in that format.
std::optional<std::uint64_t> datapath_cells(fp::Format format, IsectMode mode);

// The whole chip of a named configuration (its format), when it was synthesised.
std::optional<std::uint64_t> chip_cells(std::string_view config, IsectMode mode);

// An estimate of a configuration's chip (docs/sweeps.md, "The area estimate"), from the
// synthesis of the `default` chip (fp32): its cells with each shader core, traversal
// unit and intersection unit replaced by as many as `config` has, each core's FP units
// (fma, misc) and the ray units scaled to the format by their own synthesis; and the RAM
// bits of its caches and register files. The logic is none for a format without a
// synthesis of those units.
struct AreaEstimate {
  std::optional<std::uint64_t> logic_cells;
  std::uint64_t ram_bits = 0;
};
AreaEstimate estimate_area(const spec::HardwareConfig& config, IsectMode mode);

}  // namespace rpu::sweep
