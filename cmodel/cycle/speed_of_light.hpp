// The frame's speed of light (docs/cycle-model.md "Statistics"): each resource's work
// at full rate, with every cache access a hit and no queueing, over its units.
#pragma once

#include <vector>

#include "cycle/cycle_stats.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

namespace rpu::cycle {

// The bounds of a launch whose counts `stats` holds, on `config` with the `mode` test,
// largest first: shader issue slots, traversal units (their cycles with the IU's
// latency), intersection-unit issue slots, the DRAM bus.
std::vector<Bound> speed_of_light(const CycleStats& stats, const spec::HardwareConfig& config, IsectMode mode);

}  // namespace rpu::cycle
