// The ray dispatch alone (cycle/dispatch.hpp, rtl/rpu_ray_dispatch.sv): the cores'
// queues served in round robin, and a pipelined unit's one ray a cycle.
#include <gtest/gtest.h>

#include <optional>
#include <utility>
#include <vector>

#include "cycle/dispatch.hpp"

namespace rpu::cycle {
namespace {

// A ray of `core`, told apart by `id` (its destination register).
Ray ray(std::uint32_t core, std::uint32_t id) {
  Ray r;
  r.core = core;
  r.dst = id;
  return r;
}

// The ids next() gives until none is left.
std::vector<std::uint32_t> drain(RayDispatch& d) {
  std::vector<std::uint32_t> ids;
  while (const std::optional<Ray> r = d.next()) ids.push_back(r->dst);
  return ids;
}

TEST(RayDispatch, ServesTheCoresInRoundRobinAfterTheOneServedLastEachInOrder) {
  RayDispatch d(3);
  d.queue(ray(0, 1), 0);
  d.queue(ray(0, 2), 0);
  d.queue(ray(2, 3), 0);
  d.queue(ray(1, 4), 0);
  EXPECT_EQ(d.waiting(0), 2u);
  EXPECT_EQ(d.waiting(1), 1u);
  // Core 0 counts as served last at the start: core 1, 2, 0, then 0 again (1 and 2 are
  // empty).
  EXPECT_EQ(drain(d), (std::vector<std::uint32_t>{4, 3, 1, 2}));
  EXPECT_FALSE(d.any_waiting());
}

// A walker takes the next ray even before it arrives (it starts it when it does).
TEST(RayDispatch, NextTakesARayWhateverItsArrival) {
  RayDispatch d(1);
  d.queue(ray(0, 7), 100);
  const std::optional<Ray> r = d.next();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->arrived, 100u);
}

// The ray a cycle's send gives, and its unit.
std::optional<std::pair<std::size_t, std::uint32_t>> sent(RayDispatch& d, Cycle now, const std::vector<bool>& takes) {
  const std::optional<RayDispatch::Sent> s = d.send(now, takes);
  if (!s) return std::nullopt;
  return std::pair{s->unit, s->ray.dst};
}

TEST(RayDispatch, SendsTheNextArrivedRayToTheLowestUnitThatTakesIt) {
  RayDispatch d(2);
  d.queue(ray(0, 1), 10);
  d.queue(ray(1, 2), 5);
  d.queue(ray(1, 3), 5);
  const std::vector<bool> both{true, true}, second{false, true}, none{false, false};
  EXPECT_FALSE(d.send(4, both));  // none has arrived
  EXPECT_EQ(sent(d, 5, second), std::pair(std::size_t{1}, 2u));  // core 0's has not arrived
  EXPECT_FALSE(d.send(6, none));
  EXPECT_EQ(sent(d, 6, both), std::pair(std::size_t{0}, 3u));
  EXPECT_FALSE(d.send(9, both));
  EXPECT_EQ(sent(d, 10, both), std::pair(std::size_t{0}, 1u));
  EXPECT_FALSE(d.any_waiting());
}

// A packet's rays go to the unit that took its first, one after another; while that unit
// takes none, other cores send to other units, never to it.
TEST(RayDispatch, APacketHoldsItsUnitWhileOtherCoresSendToOthers) {
  RayDispatch d(2, true);
  const auto packet_ray = [](std::uint32_t core, std::uint32_t id, bool end) {
    Ray r = ray(core, id);
    r.packet_end = end;
    return r;
  };
  d.queue(packet_ray(0, 1, false), 0);
  d.queue(packet_ray(0, 2, true), 0);
  d.queue(packet_ray(1, 3, false), 0);
  d.queue(packet_ray(1, 4, true), 0);
  const std::vector<bool> both{true, true}, first{true, false}, second{false, true};
  EXPECT_EQ(sent(d, 0, both), std::pair(std::size_t{0}, 3u));  // core 1 first: core 0 counts as served last
  // Core 1's packet holds unit 0: core 0 opens its packet on unit 1 ...
  EXPECT_EQ(sent(d, 1, both), std::pair(std::size_t{1}, 1u));
  // ... and while unit 0 takes nothing, core 1 waits and core 0 goes on with its packet.
  EXPECT_EQ(sent(d, 2, second), std::pair(std::size_t{1}, 2u));
  // Unit 1 is free again but core 1's packet still holds unit 0.
  EXPECT_FALSE(d.send(3, second));
  EXPECT_EQ(sent(d, 4, first), std::pair(std::size_t{0}, 4u));
  EXPECT_FALSE(d.any_waiting());
}

}  // namespace
}  // namespace rpu::cycle
