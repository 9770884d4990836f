// The traversal units' timing alone (cycle/ray_unit_timing.hpp): walkers and pipelined
// units built from named configurations, driven through their ports on scripted walks,
// against cycles counted by hand from the step costs (docs/cycle-model.md "Traversal
// and intersection units").
#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

#include "common/hardware_config.hpp"
#include "cycle/event_queue.hpp"
#include "cycle/tu_pipe_timing.hpp"
#include "cycle/walker_timing.hpp"

namespace rpu::cycle {
namespace {

using Kind = functional::TraceEvent::Kind;

// A memory that answers every read kLatency cycles after it is asked.
constexpr Cycle kLatency = 7;
class FixedLatencyLines final : public LineSource {
 public:
  Cycle read(Cycle now, std::uint32_t, std::uint32_t, bool) override { return now + kLatency; }
};

// The ports as the chip wires them, around a dispatch of one core; each answer is kept
// as (the ray's dst, its cycle).
class Ports final : public RayUnitTiming::Ports {
 public:
  void queue(std::uint32_t id, std::initializer_list<functional::TraceEvent> events, Cycle at = 0) {
    Ray ray;
    ray.dst = id;
    ray.log.events = events;
    dispatch_.queue(std::move(ray), at);
  }
  std::optional<Ray> next_ray(Cycle) override { return dispatch_.next(); }
  // One ray a cycle, to the first unit that asks for one in it.
  std::optional<Ray> send_ray(Cycle now, std::size_t unit) override {
    if (asked_in_ == now) return std::nullopt;
    asked_in_ = now;
    std::vector<bool> takes(unit + 1, false);
    takes[unit] = true;
    std::optional<RayDispatch::Sent> sent = dispatch_.send(now, takes);
    return sent ? std::optional<Ray>(std::move(sent->ray)) : std::nullopt;
  }
  bool rays_waiting() const override { return dispatch_.any_waiting(); }
  void answer(Ray& ray, Cycle now) override { answers.emplace_back(ray.dst, now); }

  std::vector<std::pair<std::uint32_t, Cycle>> answers;

 private:
  RayDispatch dispatch_{1};
  Cycle asked_in_ = kNever;
};
using Answers = std::vector<std::pair<std::uint32_t, Cycle>>;

// The units run as the chip's event loop runs them: offered the rays waiting from cycle
// 0, then each in the cycles it asks for, until none asks again.
void run(const std::vector<std::unique_ptr<RayUnitTiming>>& units) {
  EventQueue events(units.size());
  for (std::uint32_t u = 0; u < units.size(); ++u) events.wake(u, units[u]->ray_waiting(0));
  while (const std::optional<EventQueue::Wakeup> w = events.next()) {
    events.wake(w->agent, units[w->agent]->advance(w->at));
  }
}

struct Walkers {
  WalkCosts costs = WalkCosts::of(hardware_config("default"), IsectMode::kWoop);
  Cycle memory = kLatency + costs.memory_wait;  // every line: the memory, then the chip's registers
  FixedLatencyLines lines;
  std::vector<IuTimer> ius;
  Ports ports;
  Timeline timeline;  // records nothing
  std::vector<std::unique_ptr<RayUnitTiming>> units;

  Walkers(int walkers, int iu_count) : ius(static_cast<std::size_t>(iu_count)) {
    for (int w = 0; w < walkers; ++w) {
      units.push_back(std::make_unique<WalkerTiming>(costs, lines, ius, ports, timeline, "TU 0"));
    }
  }
};

// Each step of the walk costs its work and its line's wait: set-up; an inner node's
// line, then its step; a leaf's line and its step; the ref's line; the record's line,
// then the IU's latency and the wait for its answer; a pop; the last leaf. The walk ends
// (and its answer leaves) in the cycle after the last step's.
TEST(WalkerTiming, TimesEachStepOfTheWalk) {
  Walkers w(1, 1);
  const WalkCosts& c = w.costs;
  w.ports.queue(1, {{Kind::kInner, 0x100}, {Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300},
                    {Kind::kPop, 0}, {Kind::kLeaf, 0x110}});
  run(w.units);
  const Cycle end = c.setup + (w.memory + c.inner) + (w.memory + c.leaf) + w.memory +
                    (w.memory + c.iu_latency + c.iu_wait) + c.pop + (w.memory + c.leaf);
  EXPECT_EQ(w.ports.answers, (Answers{{1, end}}));
  const TraversalUnitTime t = w.units[0]->time(end + 1);
  EXPECT_EQ(t.busy, c.setup + c.inner + 2 * c.leaf + c.pop);
  EXPECT_EQ(t.wait_memory, 5 * w.memory);
  EXPECT_EQ(t.wait_iu, c.iu_latency + c.iu_wait);
  EXPECT_EQ(t.idle, 1u);  // the cycle the answer leaves in
  EXPECT_EQ(t.rays, 1u);
  EXPECT_EQ(t.inner, 1u);
  EXPECT_EQ(t.leaves, 2u);
  EXPECT_EQ(t.refs, 1u);
  EXPECT_EQ(t.tests, 1u);
  EXPECT_EQ(t.pops, 1u);
}

// A walker takes the next ray `turnaround` cycles after its answer left, or when that
// ray arrives, if later.
TEST(WalkerTiming, TakesTheNextRayAfterItsTurnaroundOrItsArrival) {
  Walkers w(1, 1);
  const WalkCosts& c = w.costs;
  const Cycle walk = c.setup + w.memory + c.leaf;  // a walk of one leaf
  const Cycle late = 10 * walk;
  w.ports.queue(1, {{Kind::kLeaf, 0x100}});
  w.ports.queue(2, {{Kind::kLeaf, 0x100}});
  w.ports.queue(3, {{Kind::kLeaf, 0x100}}, late);
  run(w.units);
  EXPECT_EQ(w.ports.answers, (Answers{{1, walk}, {2, walk + c.turnaround + walk}, {3, late + walk}}));
}

// Two walkers test at once: with one IU the second waits an initiation interval, with
// two each takes one.
TEST(WalkerTiming, TestsGoToTheIntersectionUnitFreeFirst) {
  for (const int iu_count : {1, 2}) {
    Walkers w(2, iu_count);
    const WalkCosts& c = w.costs;
    w.ports.queue(1, {{Kind::kTest, 0x300}});
    w.ports.queue(2, {{Kind::kTest, 0x300}});
    run(w.units);
    const Cycle first = c.setup + w.memory + c.iu_latency + c.iu_wait;
    EXPECT_EQ(w.ports.answers, (Answers{{1, first}, {2, iu_count == 1 ? first + c.iu_interval : first}})) << iu_count;
  }
}

struct Pipes {
  PipeCosts costs = PipeCosts::of(hardware_config("rpu2005"), IsectMode::kWoop);
  Cycle memory = kLatency + costs.memory_wait;
  FixedLatencyLines lines;
  std::vector<IuTimer> ius{1};
  Ports ports;
  std::vector<std::unique_ptr<RayUnitTiming>> units;

  explicit Pipes(int count) {
    costs.packet = 1;  // the hand-written walks below are single rays'
    for (int u = 0; u < count; ++u) units.push_back(std::make_unique<PipeUnitTiming>(costs, lines, ius, ports));
  }
  // A ray's cycles through the unit, from the dispatch's cycle to its answer, for a walk
  // of `inner` inner nodes and a leaf of one triangle (rtl/rpu_tu_pipe.sv's stages):
  //   cycle 0: the ray enters a set-up engine's buffer, 1: the engine takes it, 1 +
  //   handoff: it offers the ray, a free slot takes it; the cycle after, the slot asks
  //   for its first node's line, back `memory` later. An inner node's line is at the
  //   slot's next fetch `node` cycles after it is back. The leaf's line back, the ref is
  //   asked the cycle after, and back `memory` later; the cycle after, the record's 3
  //   lines are asked, one a cycle, the last back `memory` later; the test goes to the
  //   IU the cycle after, its answer comes iu_latency + iu_wait later; the cycle after,
  //   the leaf ends, the next its pop pass enters the node-step pipeline and decides
  //   `node` - 1 cycles later that the ray is done; then the finish stage takes it, and
  //   in the cycle after that it leaves through the response arbiter.
  Cycle ray_cycles(Cycle inner) const {
    const PipeCosts& c = costs;
    const Cycle leaf_back = 1 + c.handoff + 1 + inner * (memory + c.node) + memory;
    const Cycle ref_back = leaf_back + 1 + memory;
    const Cycle record_back = ref_back + c.record_lines + memory;
    const Cycle test_answer = record_back + 1 + c.iu_latency + c.iu_wait;
    return test_answer + 1 + 1 + (c.node - 1) + 1 + 1;
  }
};

TEST(PipeUnitTiming, TimesARayThroughItsStages) {
  for (const Cycle inner : {0, 1}) {
    Pipes p(1);
    if (inner) {
      p.ports.queue(1, {{Kind::kInner, 0x100}, {Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300}});
    } else {
      p.ports.queue(1, {{Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300}});
    }
    run(p.units);
    const Cycle end = p.ray_cycles(inner);
    EXPECT_EQ(p.ports.answers, (Answers{{1, end}})) << inner << " inner nodes";
    // Slot-cycles: every slot's every cycle is busy, waiting or idle.
    const TraversalUnitTime t = p.units[0]->time(end + 1);
    EXPECT_EQ(t.busy + t.wait_memory + t.wait_iu + t.idle, (end + 1) * p.costs.slots);
    EXPECT_EQ(t.rays, 1u);
    EXPECT_EQ(t.inner, inner);
    EXPECT_EQ(t.leaves, 1u);
    EXPECT_EQ(t.refs, 1u);
    EXPECT_EQ(t.tests, 1u);
  }
}

// The dispatch sends one ray a cycle to all units: in cycle 0 the first unit takes the
// first ray and the second unit none; in cycle 1 the first unit, which runs first in it,
// takes the second ray into its set-up engine's buffer. The engine takes it when it has
// offered the first (at 1 + handoff), the cycle after: the second ray's stages are the
// first's, handoff + 1 cycles later.
TEST(PipeUnitTiming, TheDispatchSendsOneRayACycleToAllUnits) {
  Pipes p(2);
  p.ports.queue(1, {{Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300}});
  p.ports.queue(2, {{Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300}});
  run(p.units);
  const Cycle end = p.ray_cycles(0);
  EXPECT_EQ(p.ports.answers, (Answers{{1, end}, {2, end + p.costs.handoff + 1}}));
}

// A line that misses holds every later line when the port answers in order, and none
// when it answers by tag: ray 1's leaf line takes 400 cycles, ray 2's lines kLatency.
// By tag, ray 2 leaves when it would with no slow line at all (the dispatch's second
// ray, as above) and ray 1 its slow line's extra cycles later than its own unhindered
// walk; in order, ray 2 leaves only after ray 1's line is back.
class SlowLeafLine final : public LineSource {
 public:
  Cycle read(Cycle now, std::uint32_t address, std::uint32_t, bool) override {
    return now + (address == 0x108 ? kSlow : kLatency);
  }
  static constexpr Cycle kSlow = 400;
};

TEST(PipeUnitTiming, ByTagALineBackEarlyPassesALineThatWaits) {
  const Pipes fast(1);
  const Cycle unhindered = fast.ray_cycles(0);
  for (const bool by_tag : {false, true}) {
    PipeCosts costs = fast.costs;
    costs.by_tag = by_tag;
    SlowLeafLine lines;
    std::vector<IuTimer> ius{1};
    Ports ports;
    std::vector<std::unique_ptr<RayUnitTiming>> units;
    units.push_back(std::make_unique<PipeUnitTiming>(costs, lines, ius, ports));
    ports.queue(1, {{Kind::kLeaf, 0x108}, {Kind::kRef, 0x200}, {Kind::kTest, 0x300}});
    ports.queue(2, {{Kind::kLeaf, 0x110}, {Kind::kRef, 0x204}, {Kind::kTest, 0x330}});
    run(units);
    ASSERT_EQ(ports.answers.size(), 2u);
    const Cycle slow_back = 1 + costs.handoff + 1 + SlowLeafLine::kSlow + costs.memory_wait;
    if (by_tag) {
      EXPECT_EQ(ports.answers, (Answers{{2, unhindered + costs.handoff + 1},
                                        {1, unhindered + SlowLeafLine::kSlow - kLatency}}));
    } else {
      EXPECT_EQ(ports.answers.front().first, 1u);
      EXPECT_GT(ports.answers.back().second, slow_back);
      EXPECT_GT(ports.answers.front().second, slow_back);
    }
  }
}

// rpu_top's cache arbiter keeps log2(the units of its cache pair) of the cache's 6 tag
// bits for itself, and a unit keeps as many lines in flight as the rest name
// (docs/cycle-model.md): 64 with one unit a pair (rpu2005's one unit, drpu's four with a
// pair each), 32 with two, 16 with four (default's, one pair).
TEST(PipeCosts, TheUnitKeepsTheLinesItsTagBitsName) {
  EXPECT_EQ(PipeCosts::of(hardware_config("rpu2005"), IsectMode::kWoop).lines, 64u);
  EXPECT_EQ(PipeCosts::of(hardware_config("drpu"), IsectMode::kWoop).lines, 64u);
  EXPECT_EQ(PipeCosts::of(hardware_config("default"), IsectMode::kWoop).lines, 16u);
  spec::HardwareConfig pairs = hardware_config("default");
  pairs.ray_caches = 2;
  EXPECT_EQ(PipeCosts::of(pairs, IsectMode::kWoop).lines, 32u);
}

}  // namespace
}  // namespace rpu::cycle
