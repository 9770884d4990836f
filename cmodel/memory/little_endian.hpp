#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace rpu {

// Explicit little-endian stores and loads, byte by byte, so the image is the same on
// any host and no struct layout or padding of the host compiler leaks into it. The
// caller has checked that [at, at + size) lies inside the span.

inline void store_u32(std::span<std::uint8_t> out, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) out[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline void store_f32(std::span<std::uint8_t> out, std::size_t at, float v) {
  store_u32(out, at, std::bit_cast<std::uint32_t>(v));
}
inline void store_float4(std::span<std::uint8_t> out, std::size_t at, const glm::vec4& v) {
  for (int i = 0; i < 4; ++i) store_f32(out, at + 4 * static_cast<std::size_t>(i), v[i]);
}

inline std::uint32_t load_u32(std::span<const std::uint8_t> in, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(in[at + i]) << (8 * i);
  return v;
}
inline float load_f32(std::span<const std::uint8_t> in, std::size_t at) {
  return std::bit_cast<float>(load_u32(in, at));
}
inline glm::vec4 load_float4(std::span<const std::uint8_t> in, std::size_t at) {
  return {load_f32(in, at), load_f32(in, at + 4), load_f32(in, at + 8), load_f32(in, at + 12)};
}

}  // namespace rpu
