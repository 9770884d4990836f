#pragma once

#include <cstdint>
#include <memory>

#include "cycle/memory_system.hpp"
#include "device/device.hpp"

namespace rpu::cycle {

struct CycleOptions {
  std::uint64_t watchdog = 50'000'000;  // instructions per thread and pixel, as functional
  // The timeline's window [begin, end) in cycles; empty records none.
  Cycle timeline_begin = 0, timeline_end = 0;
};

// The cycle-approximate backend (docs/cycle-model.md): the functional shader core and
// tracer compute every result; this model decides when each step happens. One host
// thread; the same inputs give the same cycles. stats().cycle holds the timing.
std::unique_ptr<device::Device> make_cycle_device(const spec::HardwareConfig& config, fp::Format format,
                                                  const CycleOptions& options = {});

}  // namespace rpu::cycle
