// The separating-axis triangle/box test on cases decided by hand.
#include <gtest/gtest.h>

#include "accel/triangle_box.hpp"

namespace rpu::accel {
namespace {

const glm::dvec3 kLo(0.0), kHi(1.0);

TEST(TriangleBox, ATriangleInsideOrThroughTheBoxOverlaps) {
  EXPECT_TRUE(triangle_overlaps_box({0.2, 0.2, 0.5}, {0.8, 0.2, 0.5}, {0.2, 0.8, 0.5}, kLo, kHi));
  EXPECT_TRUE(triangle_overlaps_box({-5, -5, 0.5}, {5, -5, 0.5}, {0, 10, 0.5}, kLo, kHi));  // the box inside it
}

TEST(TriangleBox, TouchingCounts) {
  EXPECT_TRUE(triangle_overlaps_box({1, 0, 0}, {2, 0, 0}, {1, 1, 0}, kLo, kHi));  // shares an edge with a face
  EXPECT_TRUE(triangle_overlaps_box({1, 1, 1}, {2, 1, 1}, {1, 2, 1}, kLo, kHi));  // a vertex on a corner
}

TEST(TriangleBox, BoxesOverlapButTheTriangleMisses) {
  // Across the corner (1, 1, *) outside the box: x + y = 2.2 cuts the boxes' overlap
  // but not the box (the edge normal separates them).
  EXPECT_FALSE(triangle_overlaps_box({2.2, 0.0, 0.5}, {0.0, 2.2, 0.5}, {2.2, 2.2, 0.5}, kLo, kHi));
  // The plane x + y + z = 3.3 passes beyond the corner (1, 1, 1): the triangle's normal separates.
  EXPECT_FALSE(triangle_overlaps_box({3.3, 0, 0}, {0, 3.3, 0}, {0, 0, 3.3}, kLo, kHi));
  EXPECT_TRUE(triangle_overlaps_box({2.9, 0, 0}, {0, 2.9, 0}, {0, 0, 2.9}, kLo, kHi));
}

TEST(TriangleBox, ApartAlongAnAxisMisses) {
  EXPECT_FALSE(triangle_overlaps_box({1.1, 0, 0}, {2, 0, 0}, {1.1, 1, 0}, kLo, kHi));
}

}  // namespace
}  // namespace rpu::accel
