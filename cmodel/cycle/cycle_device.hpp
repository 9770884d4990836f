#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "cycle/cycle_stats.hpp"
#include "cycle/memory_system.hpp"
#include "cycle/timeline.hpp"
#include "device/device.hpp"

namespace rpu::cycle {

struct CycleOptions {
  std::uint64_t watchdog = 50'000'000;  // instructions per thread and pixel, as functional
  // The timeline's window [begin, end) in cycles; empty records none. Each slice goes to
  // `timeline` once no later cycle can extend it, so the frame keeps only a few.
  Cycle timeline_begin = 0, timeline_end = 0;
  std::function<void(const TimelineSlice&)> timeline;
  // Slices at most (about 70 bytes of JSON each); the rest of the window is cut and
  // CycleStats::timeline_cut_at says where.
  std::uint64_t timeline_max_slices = 2'000'000;
  // Called with the frame's typed statistics as it ends (also when it faults), for
  // what the report tree does not hold: the per-pixel cycles, the timeline's cut.
  std::function<void(const CycleStats&)> frame_stats;
};

// The cycle-approximate backend (docs/cycle-model.md): the functional shader core and
// tracer compute every result; this model decides when each step happens. One host
// thread; the same inputs give the same cycles. stats().report holds the timing
// (cycle::report).
std::unique_ptr<device::Device> make_cycle_device(const spec::HardwareConfig& config, fp::Format format,
                                                  const CycleOptions& options = {});

}  // namespace rpu::cycle
