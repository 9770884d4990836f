// Which thread runs which pixel (functional/pixel_map.hpp, rpu_spu's base_q): every
// pixel once, blocks in pixel order, neighbouring blocks on neighbouring cores.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "functional/pixel_map.hpp"

namespace rpu::functional {
namespace {

TEST(PixelMap, EveryPixelRunsOnceOnTheThreadItsLaneNames) {
  // 3 cores of 8 threads in chunks of 4, 101 pixels: rounds of 24, the last one partial.
  const PixelMap map(3, 8, 4, 101);
  ASSERT_EQ(map.blocks(), 26u);
  std::set<std::uint32_t> pixels;
  std::vector<ShaderCore::Lane> lanes;
  for (std::uint64_t b = 0; b < map.blocks(); ++b) {
    map.lanes(b, lanes);
    ASSERT_FALSE(lanes.empty()) << b;
    for (std::size_t l = 0; l < lanes.size(); ++l) {
      const ShaderCore::Lane& lane = lanes[l];
      EXPECT_EQ(lane.pixel, b * 4 + l) << "blocks are pixel order";
      EXPECT_EQ(lane.lane, l);
      EXPECT_EQ(lane.core, b % 3) << "neighbouring blocks on neighbouring cores";
      EXPECT_EQ(lane.chunk, b / 3 % 2);
      EXPECT_EQ(lane.thread, lane.core * 8 + lane.chunk * 4 + lane.lane);
      EXPECT_TRUE(pixels.insert(lane.pixel).second) << lane.pixel << " twice";
    }
  }
  EXPECT_EQ(pixels.size(), 101u);
  map.lanes(26, lanes);
  EXPECT_TRUE(lanes.empty()) << "past the last pixel";
}

TEST(PixelMap, AChunkRunsTheBlockOfItsCoreAndRound) {
  const PixelMap map(3, 8, 4, 1000);
  std::vector<ShaderCore::Lane> lanes;
  for (std::uint64_t round = 0; round < 4; ++round) {
    for (std::uint32_t core = 0; core < 3; ++core) {
      for (std::uint32_t chunk = 0; chunk < 2; ++chunk) {
        map.lanes(map.block(round, core, chunk), lanes);
        ASSERT_EQ(lanes.size(), 4u);
        EXPECT_EQ(lanes[0].core, core);
        EXPECT_EQ(lanes[0].chunk, chunk);
        // rpu_spu: the chunk's first pixel is (chunk x Cores + CoreId) x ChunkSize, plus
        // Cores x Threads a round.
        EXPECT_EQ(map.first_pixel(map.block(round, core, chunk)), (chunk * 3 + core) * 4 + round * 24);
      }
    }
  }
}

// On one core the map is pixel p on thread p mod T.
TEST(PixelMap, OneCoreRunsPixelPOnThreadPModT) {
  const PixelMap map(1, 32, 4, 500);
  std::vector<ShaderCore::Lane> lanes;
  for (std::uint64_t b = 0; b < map.blocks(); ++b) {
    map.lanes(b, lanes);
    for (const ShaderCore::Lane& lane : lanes) EXPECT_EQ(lane.thread, lane.pixel % 32);
  }
}

}  // namespace
}  // namespace rpu::functional
