// The ray dispatch alone (cycle/dispatch.hpp, rtl/rpu_ray_dispatch.sv): the cores'
// queues served in round robin, and a pipelined unit's one ray a cycle.
#include <gtest/gtest.h>

#include <optional>
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

TEST(RayDispatch, SendsOneArrivedRayACycle) {
  RayDispatch d(2);
  d.queue(ray(0, 1), 10);
  d.queue(ray(1, 2), 5);
  d.queue(ray(1, 3), 5);
  EXPECT_FALSE(d.send(4));  // none has arrived
  const std::optional<Ray> first = d.send(5);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->dst, 2u);  // core 0's has not arrived
  EXPECT_FALSE(d.send(5));    // one a cycle, though core 1's second has arrived
  EXPECT_EQ(d.send(6)->dst, 3u);
  EXPECT_FALSE(d.send(9));
  EXPECT_EQ(d.send(10)->dst, 1u);
  EXPECT_FALSE(d.any_waiting());
}

}  // namespace
}  // namespace rpu::cycle
