// The cycle model's DRAM and memory port (cycle/memory_system.hpp): accesses booked on
// its banks and its data bus, requests on the chip's one memory port and in a cache's
// queue to it, and a write-back cache's evictions and flush, against cycles counted by
// hand from latency, bank_busy, bytes_per_cycle and CacheDramQueue (docs/cycle-model.md
// "Memory").
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
    .bytes = 1024, .line_bytes = 64, .ways = 2, .hit_latency = 2, .mshrs = 2, .write_back = 0, .sets = 8, .index_bits = 3};
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

constexpr spec::CacheConfig kWriteBackCache{.bytes = 1024, .line_bytes = 64, .ways = 2, .hit_latency = 2, .mshrs = 2,
                                            .write_back = 1, .sets = 8, .index_bits = 3};

// Line 0 read at 0: looked up at 2, passes the port at 2, bank 0 gives its data over
// 12..16, installed with line_wait 3 at 19.
TEST(WriteBackCache, AStoreToAPresentLineStaysInTheCache) {
  Dram dram(kDram);
  Cache cache(kWriteBackCache, dram, 3);
  EXPECT_EQ(cache.read(0, 0, 16), 19u);
  EXPECT_EQ(cache.write(20, 0, 4), 20u);
  EXPECT_EQ(dram.stats().writes, 0u);
  // An absent line is written to memory as in a write-through cache (no allocation).
  EXPECT_EQ(cache.write(21, 128, 4), 21u);
  EXPECT_EQ(dram.stats().writes, 1u);
  EXPECT_EQ(cache.stats().writes, 2u);
  EXPECT_EQ(cache.stats().write_backs, 0u);
}

// Lines 0, 8 and 16 share set 0 of two ways. Line 0 is dirty when line 16's fill evicts
// it (the least recently read: writes leave the LRU order as it is): its DRAM answer
// comes at 66, the install one cycle later reads the victim into the eviction buffer,
// which offers it to the port two cycles after that, at 69: one write of the whole line.
TEST(WriteBackCache, AFillThatEvictsADirtyLineWritesItBack) {
  Dram dram(kDram);
  Cache cache(kWriteBackCache, dram, 3);
  EXPECT_EQ(cache.read(0, 0, 16), 19u);
  cache.write(20, 0, 4);
  EXPECT_EQ(cache.read(30, 8 * kLine, 16), 49u);  // into the invalid way: nothing evicted
  EXPECT_EQ(cache.stats().write_backs, 0u);
  EXPECT_EQ(cache.read(50, 16 * kLine, 16), 69u);
  EXPECT_EQ(cache.stats().write_backs, 1u);
  EXPECT_EQ(dram.stats().writes, 1u);
  EXPECT_EQ(dram.stats().bytes_written, kLine);
  EXPECT_EQ(dram.pass_port(69), 70u);  // the write-back holds the port at 69
}

// The flush walks set by set, a way a cycle, from 100: line 0 (set 0, way 0) is read at
// 100 and passes the port at 102, so the buffer is free again at 103; line 1 (set 1,
// way 0), reached at 102, waits for it, passes at 105, and the cache is idle at 106.
TEST(WriteBackCache, TheFlushWritesEveryDirtyLineThroughTheEvictionBuffer) {
  Dram dram(kDram);
  Cache cache(kWriteBackCache, dram, 3);
  cache.read(0, 0, 16);
  cache.read(1, kLine, 16);
  cache.read(2, 2 * kLine, 16);  // stays clean
  cache.write(30, 0, 4);
  cache.write(31, kLine + 16, 4);
  EXPECT_EQ(cache.flush(100), 106u);
  EXPECT_EQ(cache.stats().write_backs, 2u);
  EXPECT_EQ(dram.stats().writes, 2u);
  EXPECT_EQ(cache.flush(200), 200u);  // nothing dirty is left
}

TEST(WriteBackCache, AWriteThroughCacheHasNothingToFlush) {
  Dram dram(kDram);
  Cache cache(kCache, dram, 3);
  cache.read(0, 0, 16);
  cache.write(30, 0, 4);
  EXPECT_EQ(dram.stats().writes, 1u);
  EXPECT_EQ(cache.flush(100), 100u);
  EXPECT_EQ(dram.stats().writes, 1u);
}

}  // namespace
}  // namespace rpu::cycle
