// Which thread runs which pixel, as rpu_spu assigns them (docs/chip.md "Pixels and
// threads"): the frame's pixels in blocks of chunk_size, one block a chunk's work for a
// round. Block b runs in round b / (cores x chunks), on chunk b mod (cores x chunks) /
// cores of core b mod cores: neighbouring blocks run on neighbouring cores, so every
// core sees every part of the image and none idles while another renders the object
// in the middle. Block order is pixel order (the first fault is the first in it).
#pragma once

#include <cstdint>
#include <vector>

#include "functional/shader_core.hpp"
#include "rpu/spec.hpp"

namespace rpu::functional {

class PixelMap {
 public:
  PixelMap(std::uint32_t cores, std::uint32_t threads_per_core, std::uint32_t chunk_size, std::uint64_t pixels)
      : cores_(cores), chunks_(threads_per_core / chunk_size), size_(chunk_size), per_core_(threads_per_core),
        pixels_(pixels) {}
  // A configuration's chip rendering `pixels` pixels.
  static PixelMap of(const spec::HardwareConfig& config, std::uint64_t pixels) {
    return {static_cast<std::uint32_t>(config.shader_cores), static_cast<std::uint32_t>(config.threads_per_core),
            static_cast<std::uint32_t>(config.chunk_size), pixels};
  }

  // Blocks in the frame; the last may be partly past its last pixel.
  std::uint64_t blocks() const { return (pixels_ + size_ - 1) / size_; }
  // The block chunk `chunk` of core `core` runs in round `round`.
  std::uint64_t block(std::uint64_t round, std::uint32_t core, std::uint32_t chunk) const {
    return (round * chunks_ + chunk) * cores_ + core;
  }
  std::uint64_t first_pixel(std::uint64_t block) const { return block * size_; }
  // The lanes of a block, empty past the frame's last pixel.
  void lanes(std::uint64_t block, std::vector<ShaderCore::Lane>& out) const {
    out.clear();
    const auto core = static_cast<std::uint32_t>(block % cores_);
    const auto chunk = static_cast<std::uint32_t>(block / cores_ % chunks_);
    for (std::uint32_t l = 0; l < size_; ++l) {
      const std::uint64_t p = block * size_ + l;
      if (p >= pixels_) break;
      out.push_back({core * per_core_ + chunk * size_ + l, core, chunk, l, static_cast<std::uint32_t>(p)});
    }
  }

 private:
  std::uint32_t cores_, chunks_, size_, per_core_;
  std::uint64_t pixels_;
};

}  // namespace rpu::functional
