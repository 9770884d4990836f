#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/stats_tree.hpp"
#include "cycle/memory_system.hpp"
#include "functional/shader_core.hpp"

// What the cycle model reports for a frame (docs/cycle-model.md "Statistics").
namespace rpu::cycle {

// Every cycle of the frame falls in exactly one of busy, one of the waits, or idle.
struct ShaderCoreTime {
  std::uint64_t busy = 0;             // a chunk-instruction issued
  std::uint64_t wait_trace = 0;       // every live chunk waits for a ray
  std::uint64_t wait_memory = 0;      // the next chunk to issue waits for a load
  std::uint64_t wait_dependency = 0;  // ... for an arithmetic result or a branch
  std::uint64_t idle = 0;             // no live chunk (before the first, after the last)
  std::uint64_t chunk_issues = 0;
  // The cycles its busiest sfu held threads, each from its start until its value left S0
  // (the cycle model's; the RTL has no counter for it).
  std::uint64_t sfu_busy = 0;
  // The S0 cycles its chunk instructions' lanes needed: one per group of issue_lanes
  // lanes for an instruction of spec/isa.toml [issue], one per lane for the others
  // (the cycle model's: the issue bound).
  std::uint64_t issue_slots = 0;
};

struct TraversalUnitTime {
  std::uint64_t busy = 0;         // set-up, node, leaf and pop cycles
  std::uint64_t wait_memory = 0;  // waiting for the node or triangle cache
  std::uint64_t wait_iu = 0;      // waiting for an intersection result
  std::uint64_t idle = 0;
  std::uint64_t rays = 0, inner = 0, leaves = 0, refs = 0, tests = 0, pops = 0;

  TraversalUnitTime& operator+=(const TraversalUnitTime& o) {
    busy += o.busy;
    wait_memory += o.wait_memory;
    wait_iu += o.wait_iu;
    idle += o.idle;
    rays += o.rays;
    inner += o.inner;
    leaves += o.leaves;
    refs += o.refs;
    tests += o.tests;
    pops += o.pops;
    return *this;
  }
};

// Rays of one mode (closest or any hit), from reaching the dispatch to their answer:
// cycles waiting for a unit to take them, and in the unit (set-up, walk and answer).
struct RayLatency {
  std::uint64_t rays = 0, waiting = 0, in_unit = 0;

  RayLatency& operator+=(const RayLatency& o) {
    rays += o.rays;
    waiting += o.waiting;
    in_unit += o.in_unit;
    return *this;
  }
};

struct IntersectionUnitTime {
  std::uint64_t tests = 0;
  std::uint64_t busy = 0;  // issue slots used: tests x interval
};

// The frame's lower bound per resource: its work at full rate with every cache
// access a hit and no queueing, over its units. The largest is the speed of light.
struct Bound {
  std::string unit;
  double cycles = 0;
};

struct CycleStats {
  std::string config;
  int clock_mhz = 0;
  Cycle cycles = 0;
  double frame_seconds() const { return static_cast<double>(cycles) / (clock_mhz * 1e6); }
  std::vector<ShaderCoreTime> cores;
  std::vector<TraversalUnitTime> tus;  // per unit, its ray slots' times summed
  std::uint32_t tu_slots = 1;          // ray slots per traversal unit
  std::vector<IntersectionUnitTime> ius;
  // The ray_caches pairs' node and triangle caches together (add_ray_caches), all cores'
  // data caches.
  CacheStats node_cache, triangle_cache, data_cache;
  // The lookups of the busiest node and of the busiest triangle cache (one a cycle each).
  std::uint64_t node_port_lookups = 0, triangle_port_lookups = 0;
  DramStats dram;
  int dram_bytes_per_cycle = 0;
  std::uint64_t closest_rays = 0, any_rays = 0;
  // The cycle model's (the chip has no counters for it: the rtl backend's stay empty).
  RayLatency closest_latency, any_latency;
  std::uint64_t thread_instructions = 0;
  bool counts_pops = true;    // the RTL's traversal units count no stack pops
  std::vector<Bound> bounds;  // largest first
  double host_seconds = 0;
  // Per pixel (row 0 first): cycles from its thread's start to its halt.
  int width = 0, height = 0;
  std::vector<std::uint32_t> pixel_cycles;
  // The timeline's slices (CycleOptions::timeline got them); when it reached its most
  // (CycleOptions::timeline_max_slices), the begin of the first slice left out.
  std::uint64_t timeline_slices = 0;
  std::optional<Cycle> timeline_cut_at;

  // One pair's node and triangle cache: added to the totals, and to the busiest ports'.
  void add_ray_caches(const CacheStats& node, const CacheStats& triangle);

  // The frame of two launches, `o` run after this one on the same chip (a selected
  // frame, docs/selection.md): cycles, times and counts add, and so do the bounds.
  CycleStats& operator+=(const CycleStats& o);
};

// The frame's statistics as the backend reports them (device::DeviceStats::report;
// docs/cycle-model.md "Statistics" lists them).
StatsTree report(const CycleStats& stats, const functional::ShaderStats& shader);
// A few lines for the terminal, from a cycle backend's report.
std::string summarize(const StatsTree& report);
}  // namespace rpu::cycle
