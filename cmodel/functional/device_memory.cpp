#include "functional/device_memory.hpp"

#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "rpu/spec.hpp"

namespace rpu::functional {

namespace mm = spec::memory;

DeviceMemory::DeviceMemory(std::span<const std::uint8_t> image, std::vector<std::uint8_t> launch_block,
                           std::vector<std::uint8_t> data, std::uint32_t framebuffer_pixels)
    : image_(image),
      launch_(std::move(launch_block)),
      data_(std::move(data)),
      framebuffer_(std::size_t{framebuffer_pixels} * mm::kFramebufferBytesPerPixel, 0) {
  const auto seg = [](std::string_view name, std::uint32_t base, std::span<const std::uint8_t> bytes) {
    return Segment{name, base, bytes.data(), static_cast<std::uint32_t>(bytes.size())};
  };
  segments_ = {seg("image", mm::kDeviceImageBase, image_), seg("launch block", mm::kDeviceLaunchBase, launch_),
               seg("data", mm::kDeviceDataBase, data_), seg("framebuffer", mm::kDeviceFramebufferBase, framebuffer_)};
}

const DeviceMemory::Segment* DeviceMemory::find(std::uint32_t address) const {
  for (const Segment& s : segments_) {
    if (address >= s.base && address - s.base < s.size) return &s;
  }
  return nullptr;
}

DeviceMemory::Access DeviceMemory::check(std::uint32_t address, std::uint32_t bytes, bool write,
                                         std::uint32_t pixel) const {
  if (address % 4) return {false, fmt::format("misaligned access at address {:#010x} (needs 4-byte alignment)", address)};
  const Segment* s = find(address);
  const std::uint64_t end = std::uint64_t{address} + bytes;
  const char* what = write ? "store" : "load";
  if (!s) {
    const bool stack = address >= mm::kDeviceStackBase && address < mm::kDeviceFramebufferBase;
    return {false, stack ? fmt::format("{} of {} bytes at address {:#010x} is in the stack segment, which only push "
                                       "and pop reach",
                                       what, bytes, address)
                         : fmt::format("{} of {} bytes at address {:#010x} is outside the device memory", what, bytes,
                                       address)};
  }
  if (end - s->base > s->size) {
    // It starts inside a segment: say which one it runs out of, not "outside the memory".
    return {false, fmt::format("{} of {} bytes at address {:#010x} runs past the end of the {} segment ({} bytes at "
                               "{:#010x})",
                               what, bytes, address, s->name, s->size, s->base)};
  }
  if (s->base == mm::kDeviceFramebufferBase) {
    const std::uint64_t own = std::uint64_t{mm::kDeviceFramebufferBase} + std::uint64_t{pixel} * mm::kFramebufferBytesPerPixel;
    if (address < own || end > own + mm::kFramebufferBytesPerPixel) {
      return {false, fmt::format("{} at framebuffer address {:#010x} outside the thread's own pixel {} "
                                 "({:#010x}..{:#010x})",
                                 write ? "store" : "load", address, pixel, own, own + mm::kFramebufferBytesPerPixel - 1)};
    }
    return {};
  }
  if (write) return {false, fmt::format("store to address {:#010x} in the read-only {} segment", address, s->name)};
  return {};
}

std::uint32_t DeviceMemory::load32(std::uint32_t address) const {
  const Segment* s = find(address);
  std::uint32_t v;
  std::memcpy(&v, s->bytes + (address - s->base), 4);
  return v;
}

void DeviceMemory::store32(std::uint32_t address, std::uint32_t value) {
  std::memcpy(framebuffer_.data() + (address - mm::kDeviceFramebufferBase), &value, 4);
}

}  // namespace rpu::functional
