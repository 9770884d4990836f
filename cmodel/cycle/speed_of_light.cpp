#include "cycle/speed_of_light.hpp"

#include <algorithm>

#include "cycle/tu_pipe_timing.hpp"
#include "cycle/walker_timing.hpp"

namespace rpu::cycle {

std::vector<Bound> speed_of_light(const CycleStats& stats, const spec::HardwareConfig& config, IsectMode mode) {
  const WalkCosts walk = WalkCosts::of(config, mode);
  const PipeCosts pipe = PipeCosts::of(config, mode);
  TraversalUnitTime tu_work;
  std::uint64_t tests = 0;
  for (const TraversalUnitTime& t : stats.tus) tu_work += t;
  for (const IntersectionUnitTime& t : stats.ius) tests += t.tests;
  const spec::TraversalUnitConfig& tc = config.tu;
  const auto node_hit = static_cast<double>(config.node_cache.hit_latency + config.tu.memory_wait);
  const auto tri_hit = static_cast<double>(config.triangle_cache.hit_latency + config.tu.memory_wait);
  // A pipelined unit: its memory port moves a line a cycle (a node, a ref, a record's
  // lines), its set-up engines take `handoff` cycles a ray.
  const double pipe_cycles = std::max(
      static_cast<double>(tu_work.inner + tu_work.leaves + tu_work.refs + tu_work.tests * pipe.record_lines),
      static_cast<double>(tu_work.rays) * static_cast<double>(pipe.handoff) / config.tu_setups);
  // A walker: each step's work, its line a hit, its test the IU's latency.
  const double walk_cycles = static_cast<double>(tu_work.rays) * static_cast<double>(walk.setup) +
                             static_cast<double>(tu_work.inner) * (node_hit + tc.inner) +
                             static_cast<double>(tu_work.leaves) * (node_hit + tc.leaf) +
                             static_cast<double>(tu_work.refs) * tri_hit +
                             static_cast<double>(tu_work.tests) *
                                 (tri_hit + static_cast<double>(walk.iu_latency + walk.iu_wait)) +
                             static_cast<double>(tu_work.pops) * tc.pop;
  // A core's sfu takes one thread at a time, and its lanes enter S0 a group of
  // issue_lanes a cycle or one a cycle (loads, stores, sfu, trace and special
  // instructions): the busiest core's sfu and S0 bound.
  std::uint64_t sfu_busy = 0, issue_slots = 0;
  for (const ShaderCoreTime& t : stats.cores) {
    sfu_busy = std::max(sfu_busy, t.sfu_busy);
    issue_slots = std::max(issue_slots, t.issue_slots);
  }
  std::vector<Bound> bounds = {
      {"shader cores (issue)", static_cast<double>(issue_slots)},
      {"sfu (busiest core)", static_cast<double>(sfu_busy)},
      {"traversal units", config.tu_pipe ? pipe_cycles / config.traversal_units
                                         : walk_cycles / (config.traversal_units * config.tu_slots)},
      {"intersection units", static_cast<double>(tests) * static_cast<double>(walk.iu_interval) / config.intersection_units},
      {"DRAM bus", static_cast<double>(stats.dram.bus_cycles)},
      // Each access holds its bank `bank_busy` cycles; the blocks interleave over the banks.
      {"DRAM banks", static_cast<double>(stats.dram.reads + stats.dram.writes) * config.dram.bank_busy /
                         config.dram.banks},
      // A node or triangle cache takes one lookup a cycle from all the traversal units
      // it serves; the busiest of the ray_caches pairs bounds.
      {"node cache port", static_cast<double>(stats.node_port_lookups)},
      {"triangle cache port", static_cast<double>(stats.triangle_port_lookups)},
  };
  std::stable_sort(bounds.begin(), bounds.end(), [](const Bound& a, const Bound& b) { return a.cycles > b.cycles; });
  return bounds;
}

}  // namespace rpu::cycle
