#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rpu::functional {

// The shader cores' address space (spec/memory_map.toml [device], docs/shader-core.md
// "Memory"): the memory image, the launch block with the shader table, the firmware's
// data (all three read-only) and the framebuffer. Every access is 4-byte aligned and
// inside one segment; the framebuffer is written by one thread per pixel, so a thread
// may touch only its own pixel's bytes. Thread stacks are not addressable: only
// push and pop reach them.
class DeviceMemory {
 public:
  DeviceMemory(std::span<const std::uint8_t> image, std::vector<std::uint8_t> launch_block,
               std::vector<std::uint8_t> data, std::uint32_t framebuffer_pixels);

  // The outcome of an access: ok, or why not (a fault message without the thread).
  struct Access {
    bool ok = true;
    std::string problem;
  };
  // `bytes` words at `address` for a thread rendering pixel `pixel`.
  Access check(std::uint32_t address, std::uint32_t bytes, bool write, std::uint32_t pixel) const;
  // After a successful check only.
  std::uint32_t load32(std::uint32_t address) const;
  void store32(std::uint32_t address, std::uint32_t value);

  std::span<const std::uint8_t> framebuffer() const { return framebuffer_; }
  std::span<const std::uint8_t> launch_block() const { return launch_; }

 private:
  struct Segment {
    std::string_view name;
    std::uint32_t base;
    const std::uint8_t* bytes;
    std::uint32_t size;
  };
  const Segment* find(std::uint32_t address) const;

  std::span<const std::uint8_t> image_;
  std::vector<std::uint8_t> launch_, data_, framebuffer_;
  std::vector<Segment> segments_;
};

}  // namespace rpu::functional
