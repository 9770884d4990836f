#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "render/selection.hpp"

namespace rpu {

// What a render is asked to do; the same for every backend.
struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 4;          // samples per pixel (jittered, see docs/shading.md)
  int max_depth = 5;    // reflection/refraction bounces after the primary hit
  std::uint32_t seed = 1;
  int threads = 0;      // host threads; 0 = all cores. The image never depends on it.
  Selection select = {};  // the firmware backends' selected ray tracing; off by default
};

// Rays traced, by type.
struct RayCounts {
  std::uint64_t primary = 0;
  std::uint64_t shadow = 0;
  std::uint64_t reflection = 0;
  std::uint64_t refraction = 0;

  std::uint64_t total() const { return primary + shadow + reflection + refraction; }
  RayCounts& operator+=(const RayCounts& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    return *this;
  }
};

// Called by whichever rendering thread finished a tile, possibly from several threads
// at once: (tiles done, tiles in all).
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace rpu
