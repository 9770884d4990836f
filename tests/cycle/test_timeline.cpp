// The cycle model's timeline alone (cycle/timeline.hpp): slices joined, clipped to the
// window, streamed once closed, and cut at their most.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cycle/timeline.hpp"

namespace rpu::cycle {
namespace {

struct Recorded {
  std::vector<TimelineSlice> slices;
  // A timeline into `slices`, its first launch started.
  Timeline timeline(Cycle begin, Cycle end, std::uint64_t max_slices) {
    Timeline t(begin, end, max_slices, [this](const TimelineSlice& s) { slices.push_back(s); });
    t.start(0, 0);
    return t;
  }
  // "track name begin+cycles" per slice, in the order the sink got them.
  std::vector<std::string> text() const {
    std::vector<std::string> out;
    for (const TimelineSlice& s : slices) {
      out.push_back(s.track + " " + s.name + " " + std::to_string(s.begin) + "+" + std::to_string(s.cycles));
    }
    return out;
  }
};

using Texts = std::vector<std::string>;

TEST(Timeline, ConsecutiveCyclesOfOneActivityOnATrackMakeOneSlice) {
  Recorded r;
  Timeline t = r.timeline(0, 100, 1000);
  t.add("core 0", "chunk 0: add", 0, 1);
  t.add("core 0", "chunk 0: add", 1, 2);  // joins the slice before
  t.add("TU 0", "set-up", 1, 5);
  t.add("core 0", "chunk 1: mul", 2, 3);
  t.add("core 0", "chunk 1: mul", 3, 4);  // joins across the other track's slice
  t.add("core 0", "chunk 1: mul", 5, 6);  // a cycle apart: a slice of its own
  t.flush();
  EXPECT_EQ(r.text(), (Texts{"core 0 chunk 0: add 0+2", "TU 0 set-up 1+4", "core 0 chunk 1: mul 2+2",
                             "core 0 chunk 1: mul 5+1"}));
  EXPECT_EQ(t.slices(), 4u);
  EXPECT_FALSE(t.cut_at());
}

TEST(Timeline, KeepsTheCyclesInTheWindowOnly) {
  Recorded r;
  Timeline t = r.timeline(10, 20, 1000);
  t.add("TU 0", "inner node", 5, 12);
  t.add("TU 0", "leaf", 18, 30);
  t.add("TU 0", "pop", 20, 24);
  t.flush();
  EXPECT_EQ(r.text(), (Texts{"TU 0 inner node 10+2", "TU 0 leaf 18+2"}));
  EXPECT_FALSE(Timeline().enabled());
}

// A slice goes to the sink once eight later ones are open, before the launch ends.
TEST(Timeline, StreamsASliceOnceEightLaterOnesAreOpen) {
  Recorded r;
  Timeline t = r.timeline(0, 100, 1000);
  for (Cycle c = 0; c < 9; ++c) t.add("core " + std::to_string(c), "halt", c, c + 1);
  EXPECT_EQ(r.text(), (Texts{"core 0 halt 0+1"}));
  t.flush();
  EXPECT_EQ(r.slices.size(), 9u);
}

// At its most the rest is cut; pass 1 of a selected frame counts pass 0's slices and
// says where the cut is in its own cycles.
TEST(Timeline, IsCutAtItsMostSlicesOverTheFrame) {
  Recorded r;
  Timeline t = r.timeline(0, 1000, 3);
  t.add("core 0", "a", 0, 1);
  t.add("core 0", "b", 1, 2);
  t.flush();
  EXPECT_EQ(t.slices(), 2u);
  t.start(50, 2);  // pass 1 after pass 0's 50 cycles and 2 slices
  t.add("core 0", "c", 4, 5);
  t.add("core 0", "d", 7, 8);
  t.add("core 0", "e", 9, 10);
  t.flush();
  EXPECT_EQ(r.text(), (Texts{"core 0 a 0+1", "core 0 b 1+1", "core 0 c 54+1"}));
  EXPECT_EQ(t.slices(), 1u);
  ASSERT_TRUE(t.cut_at());
  EXPECT_EQ(*t.cut_at(), 7u);
}

}  // namespace
}  // namespace rpu::cycle
