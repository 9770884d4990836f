// The speed-of-light bounds alone (cycle/speed_of_light.hpp): each resource's work at
// full rate over its units, the largest first.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/hardware_config.hpp"
#include "cycle/speed_of_light.hpp"

namespace rpu::cycle {
namespace {

std::vector<std::string> units(const std::vector<Bound>& bounds) {
  std::vector<std::string> out;
  for (const Bound& b : bounds) out.push_back(b.unit);
  return out;
}

// `default` (4 shader cores, 4 IUs): the busiest core's S0 cycles (its lanes' groups)
// and its sfu, which holds one thread at a time, bound; each
// DRAM access holds its bank bank_busy cycles; an IU takes a test every initiation interval; the DRAM bus is one, and so are
// the busiest node and triangle caches' ports, one lookup a cycle for the traversal units
// each serves (the caches' totals, all ray_caches pairs', do not bound).
TEST(SpeedOfLight, EachResourcesWorkOverItsUnitsLargestFirst) {
  spec::HardwareConfig config = hardware_config("default");
  CycleStats s;
  s.thread_instructions = 4000;
  s.ius = {{.tests = 200, .busy = 0}, {.tests = 100, .busy = 0}};
  s.dram.bus_cycles = 500;
  s.node_cache.accesses = 2800;
  s.triangle_cache.accesses = 200;
  s.node_port_lookups = 700;
  s.triangle_port_lookups = 50;
  s.cores = {{.sfu_busy = 120, .issue_slots = 1000},
             {.sfu_busy = 600, .issue_slots = 400},
             {.sfu_busy = 0, .issue_slots = 0},
             {.sfu_busy = 30, .issue_slots = 999}};
  s.dram.reads = 10;
  s.dram.writes = 6;
  const std::vector<Bound> b = speed_of_light(s, config, IsectMode::kWoop);
  EXPECT_EQ(units(b), (std::vector<std::string>{"shader cores (issue)", "node cache port", "sfu (busiest core)",
                                                "DRAM bus", "intersection units", "triangle cache port",
                                                "DRAM banks", "traversal units"}));
  EXPECT_EQ(b[0].cycles, 1000.0);
  EXPECT_EQ(b[1].cycles, 700.0);
  EXPECT_EQ(b[2].cycles, 600.0);
  EXPECT_EQ(b[3].cycles, 500.0);
  EXPECT_EQ(b[4].cycles, 300.0 * config.iu.interval_woop / 4);
  EXPECT_EQ(b[5].cycles, 50.0);
  EXPECT_EQ(b[6].cycles, 16.0 * config.dram.bank_busy / config.dram.banks);
  EXPECT_EQ(b[7].cycles, 0.0);
}

// A pipelined unit (`rpu2005`: one unit, 2 set-up engines) moves a line a cycle on its
// port (a node, a ref, each of a Woop record's three lines) and its engines set a ray up
// in `handoff` cycles each: its bound is the larger.
TEST(SpeedOfLight, APipelinedUnitIsBoundByItsPortOrItsSetUpEngines) {
  const spec::HardwareConfig& config = hardware_config("rpu2005");
  CycleStats s;
  s.tus.resize(1);
  s.tus[0].inner = 100;
  s.tus[0].leaves = 20;
  s.tus[0].refs = 30;
  s.tus[0].tests = 30;
  const double port = 100 + 20 + 30 + 30 * 3;
  for (const std::uint64_t rays : {1, 50}) {
    s.tus[0].rays = rays;
    const double set_up = static_cast<double>(rays * config.tu.pipe_handoff_woop) / 2;
    const std::vector<Bound> b = speed_of_light(s, config, IsectMode::kWoop);
    ASSERT_EQ(b[0].unit, "traversal units");
    EXPECT_EQ(b[0].cycles, std::max(port, set_up)) << rays << " rays";
  }
}

}  // namespace
}  // namespace rpu::cycle
