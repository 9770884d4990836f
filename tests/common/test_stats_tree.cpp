// The statistics tree and its writers (common/stats_tree.hpp): insertion order, one-line
// additions, and the three file shapes, against hand-written text.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "common/error.hpp"
#include "common/stats_tree.hpp"

namespace rpu {
namespace {

StatsTree sample() {
  StatsTree t;
  t.set("run", "a, \"quoted\" name").set("cycles", std::uint64_t{12}).set("clock_mhz", 100);
  t.group("caches").group("node").set("hit_rate", 0.5).set("hits", 3u);
  StatsTree& units = t.list("units");
  units.add().set("busy", 7u);
  units.add().set("busy", 9u);
  t.set("delta", -2);
  return t;
}

TEST(StatsTree, KeepsTheOrderOfAdditionAndReplacesAValueInPlace) {
  StatsTree t = sample();
  t.set("cycles", std::uint64_t{13});
  t.group("caches").group("node").set("misses", 1u);
  ASSERT_EQ(t.children().size(), 6u);
  EXPECT_EQ(t.children()[1].name(), "cycles");
  EXPECT_EQ(t.number("cycles"), 13.0);
  EXPECT_EQ(t.number("caches.node.misses"), 1.0);
  EXPECT_EQ(t.number("units.1.busy"), 9.0);
  EXPECT_EQ(t.number("delta"), -2.0);
  EXPECT_EQ(t.find("units.2"), nullptr);
  EXPECT_EQ(t.find("caches.none"), nullptr);
  EXPECT_THROW(t.number("run"), Error);
  EXPECT_THROW(t.group("cycles"), Error);
}

TEST(StatsTree, JsonSortsKeysAndKeepsIntegers) {
  EXPECT_EQ(stats_json(sample()),
            "{\n"
            "  \"caches\": {\n"
            "    \"node\": {\n"
            "      \"hit_rate\": 0.5,\n"
            "      \"hits\": 3\n"
            "    }\n"
            "  },\n"
            "  \"clock_mhz\": 100,\n"
            "  \"cycles\": 12,\n"
            "  \"delta\": -2,\n"
            "  \"run\": \"a, \\\"quoted\\\" name\",\n"
            "  \"units\": [\n"
            "    {\n"
            "      \"busy\": 7\n"
            "    },\n"
            "    {\n"
            "      \"busy\": 9\n"
            "    }\n"
            "  ]\n"
            "}\n");
}

TEST(StatsTree, CsvRowHasOneColumnPerMetricInTheTreesOrder) {
  EXPECT_EQ(stats_csv_row(sample()),
            "run,cycles,clock_mhz,caches.node.hit_rate,caches.node.hits,units.0.busy,units.1.busy,delta\n"
            "\"a, \"\"quoted\"\" name\",12,100,0.5,3,7,9,-2\n");
}

}  // namespace
}  // namespace rpu
