// The cycle model's event queue alone (cycle/event_queue.hpp): cycle order, the order
// of making within a cycle, one pending wake-up per agent.
#include <gtest/gtest.h>

#include <optional>
#include <utility>
#include <vector>

#include "cycle/event_queue.hpp"

namespace rpu::cycle {
namespace {

// Every wake-up left, as (cycle, agent).
std::vector<std::pair<Cycle, std::uint32_t>> drain(EventQueue& q) {
  std::vector<std::pair<Cycle, std::uint32_t>> out;
  while (const std::optional<EventQueue::Wakeup> w = q.next()) out.emplace_back(w->at, w->agent);
  return out;
}

using Order = std::vector<std::pair<Cycle, std::uint32_t>>;

TEST(EventQueue, WakeupsComeInCycleOrderAndWithinACycleInTheOrderTheyWereMade) {
  EventQueue q(4);
  q.wake(2, 10);
  q.wake(0, 5);
  q.wake(1, 10);
  q.wake(3, 7);
  EXPECT_EQ(drain(q), (Order{{5, 0}, {7, 3}, {10, 2}, {10, 1}}));
}

// A wake-up made while its cycle runs comes after the others already made for it.
TEST(EventQueue, AWakeupMadeInItsOwnCycleRunsAfterThoseMadeBefore) {
  EventQueue q(3);
  q.wake(0, 5);
  q.wake(1, 5);
  ASSERT_EQ(q.next()->agent, 0u);
  q.wake(2, 5);
  q.wake(0, 5);
  EXPECT_EQ(drain(q), (Order{{5, 1}, {5, 2}, {5, 0}}));
}

TEST(EventQueue, AnAgentHasOnePendingWakeupTheEarliest) {
  EventQueue q(2);
  q.wake(0, 20);
  q.wake(0, 8);   // replaces 20
  q.wake(1, 6);
  q.wake(1, 9);   // later than its pending 6: nothing
  q.wake(1, kNever);
  EXPECT_EQ(drain(q), (Order{{6, 1}, {8, 0}}));
  // The clock passed the replaced wake-up at 20 too.
  EXPECT_EQ(q.now(), 20u);
}

// Once its wake-up is taken an agent has none pending: a later one is made again.
TEST(EventQueue, AnAgentThatRanIsWokenAgain) {
  EventQueue q(1);
  q.wake(0, 5);
  ASSERT_EQ(q.next()->at, 5u);
  q.wake(0, 9);
  EXPECT_EQ(drain(q), (Order{{9, 0}}));
  EXPECT_EQ(q.now(), 9u);
}

}  // namespace
}  // namespace rpu::cycle
