#pragma once

#include <bit>
#include <cstdint>

#include "rpu/spec.hpp"

namespace rpu {

// One 8-byte kd-tree node as it lies in the memory image (spec/memory_map.toml
// [kd_node]; pbrt-v3's KdAccelNode). Word 0: bits [1:0] split axis 0/1/2 or 3 = leaf,
// bits [31:2] the above child's node index (inner) or the primitive count (leaf).
// Word 1: the split position as fp32 bits (inner) or the index of the leaf's first
// entry in the primitive-reference list (leaf). The below child is the next node.
struct KdNode {
  std::uint32_t word0 = 0;
  std::uint32_t word1 = 0;

  static constexpr std::uint32_t kLeafKind = spec::memory::kKdNodeLeafKind;
  static constexpr std::uint32_t kKindBits = spec::memory::kKdNodeKindBits;
  static constexpr std::uint32_t kKindMask = (1u << kKindBits) - 1u;
  static constexpr std::uint32_t kMaxIndex = (1u << spec::memory::kKdNodeIndexBits) - 1u;

  static constexpr KdNode inner(int axis, std::uint32_t above_child, float split) {
    return {(above_child << kKindBits) | static_cast<std::uint32_t>(axis), std::bit_cast<std::uint32_t>(split)};
  }
  static constexpr KdNode leaf(std::uint32_t prim_count, std::uint32_t first_prim_ref) {
    return {(prim_count << kKindBits) | kLeafKind, first_prim_ref};
  }

  constexpr bool is_leaf() const { return (word0 & kKindMask) == kLeafKind; }
  constexpr int split_axis() const { return static_cast<int>(word0 & kKindMask); }
  constexpr std::uint32_t above_child() const { return word0 >> kKindBits; }
  constexpr std::uint32_t prim_count() const { return word0 >> kKindBits; }
  constexpr std::uint32_t first_prim_ref() const { return word1; }
  constexpr std::uint32_t split_bits() const { return word1; }
  constexpr float split() const { return std::bit_cast<float>(word1); }
};
static_assert(sizeof(KdNode) == spec::memory::kKdNodeBytes);

}  // namespace rpu
