// The cycle model's DRAM alone (cycle/memory_system.hpp): accesses booked on its banks
// and its data bus, against cycles counted by hand from latency, bank_busy and
// bytes_per_cycle (docs/cycle-model.md "Memory").
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

}  // namespace
}  // namespace rpu::cycle
