// The cycle model's DRAM and memory port (cycle/memory_system.hpp): accesses booked on
// its banks and its data bus, requests on the chip's one memory port and in a cache's
// queue to it, against cycles counted by hand from latency, bank_busy, bytes_per_cycle
// and CacheDramQueue (docs/cycle-model.md "Memory").
#include <gtest/gtest.h>

#include "cycle/memory_system.hpp"

namespace rpu::cycle {
namespace {

// 10 cycles to the first data, a bank busy 4 cycles an access, 16 bytes a cycle: a
// 64-byte line holds the bus 4 cycles.
constexpr spec::DramConfig kDram{.latency = 10, .bytes_per_cycle = 16, .banks = 2, .bank_busy = 4};
constexpr std::uint32_t kLine = 64;
constexpr std::uint32_t kBank0 = 0, kBank1 = Dram::kInterleaveBytes;

TEST(Dram, AnAccessAloneTakesLatencyAndItsTransfer) {
  Dram dram(kDram);
  EXPECT_EQ(dram.access(100, kBank0, kLine, false), 100u + 10 + 4);
  EXPECT_EQ(dram.stats().bus_cycles, 4u);
  EXPECT_EQ(dram.stats().bytes_read, kLine);
}

TEST(Dram, OneBankServesOneAccessPerBankBusy) {
  Dram dram(kDram);
  EXPECT_EQ(dram.access(0, kBank0, kLine, false), 14u);
  // The bank is busy until 4; the second starts then, its data follow the first's.
  EXPECT_EQ(dram.access(1, kBank0 + 2 * Dram::kInterleaveBytes, kLine, false), 4u + 10 + 4);
}

TEST(Dram, TwoBanksShareTheBus) {
  Dram dram(kDram);
  EXPECT_EQ(dram.access(0, kBank0, kLine, false), 14u);
  // Its bank is free at 0, but the bus carries the first line over 10..14.
  EXPECT_EQ(dram.access(0, kBank1, kLine, false), 18u);
}

// An access booked after another for an earlier cycle (the event loop makes some calls
// out of time order) uses the bank and the bus before the later booking.
TEST(Dram, AnAccessBookedLateForAnEarlierCycleTakesTheGapBeforeTheLaterOne) {
  Dram dram(kDram);
  EXPECT_EQ(dram.access(1000, kBank0, kLine, false), 1014u);
  EXPECT_EQ(dram.access(100, kBank0, kLine, false), 114u);
  EXPECT_EQ(dram.access(100, kBank1, kLine, false), 118u);
}

// A gap shorter than the transfer is skipped: the bus is booked 10..14 and 16..20, so a
// 4-cycle transfer wanted from 13 goes after both.
TEST(Dram, AGapTooShortForTheTransferIsSkipped) {
  Dram dram(kDram);
  EXPECT_EQ(dram.access(0, kBank0, kLine, false), 14u);
  EXPECT_EQ(dram.access(6, kBank1, kLine, false), 20u);
  EXPECT_EQ(dram.access(3, kBank1 + 2 * Dram::kInterleaveBytes, kLine, false), 24u);
}

// Bookings that touch are one interval: a transfer wanted inside them waits for its end.
// Four lines on alternating banks hold the bus over 10..26; a 16-byte read from 11 wants
// it at 21 and gets it at 26.
TEST(Dram, BackToBackTransfersLeaveNoGap) {
  Dram dram(kDram);
  for (std::uint32_t k = 0; k < 4; ++k) EXPECT_EQ(dram.access(0, k * Dram::kInterleaveBytes, kLine, false), 14u + 4 * k);
  EXPECT_EQ(dram.access(11, 4 * Dram::kInterleaveBytes + 1, 16, false), 27u);
}

TEST(Dram, WritesAreCountedApart) {
  Dram dram(kDram);
  dram.access(0, kBank0, 8, true);
  EXPECT_EQ(dram.stats().writes, 1u);
  EXPECT_EQ(dram.stats().bytes_written, 8u);
  EXPECT_EQ(dram.stats().reads, 0u);
  EXPECT_EQ(dram.stats().bus_cycles, 1u);
}

TEST(Dram, ThePortPassesOneRequestACycle) {
  Dram dram(kDram);
  EXPECT_EQ(dram.pass_port(5), 5u);
  EXPECT_EQ(dram.pass_port(5), 6u);
  EXPECT_EQ(dram.pass_port(3), 3u);  // booked late for an earlier, free cycle
  EXPECT_EQ(dram.pass_port(5), 7u);
}

constexpr spec::CacheConfig kCache{
    .bytes = 1024, .line_bytes = 64, .ways = 2, .hit_latency = 2, .mshrs = 2, .sets = 8, .index_bits = 3};
static_assert(streams::kCacheDramQueue == 2, "the hand counts below queue two requests");

// Another cache holds the port over 0..99: a cache's stores queue in front of it, two at
// most, and the third is taken when the first's place is free, two cycles after it
// passed (the RTL's FIFO counts a pop the cycle after it).
TEST(Cache, StoresWaitForRoomInTheQueueToThePort) {
  Dram dram(kDram);
  for (Cycle c = 0; c < 100; ++c) dram.pass_port(c);
  Cache cache(kCache, dram, 3);
  EXPECT_EQ(cache.write(0, 0, 4), 0u);    // passes at 100
  EXPECT_EQ(cache.write(1, 16, 4), 1u);   // passes at 101
  EXPECT_EQ(cache.write(2, 32, 4), 102u); // passes at 102
  EXPECT_EQ(cache.write(200, 48, 4), 200u);
  EXPECT_EQ(cache.stats().writes, 4u);
  EXPECT_EQ(dram.stats().writes, 4u);
}

// A store across a piece boundary is two requests a cycle apart, each the bytes of its
// piece; a line read that misses behind them passes the port after both.
TEST(Cache, AStoreAcrossAPieceIsTwoRequests) {
  Dram dram(kDram);
  Cache cache(kCache, dram, 3);
  EXPECT_EQ(cache.write(0, 8, 16), 1u);
  EXPECT_EQ(dram.stats().writes, 2u);
  EXPECT_EQ(dram.stats().bytes_written, 16u);
  EXPECT_EQ(cache.stats().writes, 2u);
  // Looked up at 1 + 2, it passes the port at 3 (the stores passed at 0 and 1), bank 1
  // starts it then; its data would take the bus over 13..17, but the second store's
  // (bank 0, busy until 4) holds it at 14, so they take 15..19; then line_wait.
  EXPECT_EQ(cache.read(1, kBank1, 16), 19u + 3);
}

}  // namespace
}  // namespace rpu::cycle
