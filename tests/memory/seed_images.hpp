#pragma once

// The fuzzer's seed images (tests/fuzz/corpus/memory_image/): small valid images that
// cover both intersection modes, empty and full optional sections, and trees with
// inner nodes. write_seed_images writes them; a unit test checks the committed files
// are what this writes now, so a layout change cannot leave stale seeds behind.
#include <string>
#include <utility>
#include <vector>

#include "memory/memory_image.hpp"
#include "tiny_scene.hpp"

namespace rpu::test {

inline std::vector<std::pair<std::string, MemoryImage>> seed_images() {
  std::vector<std::pair<std::string, MemoryImage>> seeds;
  const Scene full = tiny_scene();
  seeds.emplace_back("woop_split.rpu", build_memory_image(full, split_tree(), IsectMode::kWoop));
  seeds.emplace_back("watertight_split.rpu", build_memory_image(full, split_tree(), IsectMode::kWatertight));
  Scene bare = full;
  bare.normals.clear();
  bare.uvs.clear();
  bare.lights.clear();
  seeds.emplace_back("woop_leaf_bare.rpu", build_memory_image(bare, single_leaf_tree(4), IsectMode::kWoop));
  return seeds;
}

}  // namespace rpu::test
