#include "host_setup.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "common/error.hpp"
#include "rpu/spec.hpp"

namespace rpu::sim {

namespace mm = spec::memory;

std::uint32_t PixelDivisor::quotient(std::uint32_t p) const {
  const auto t1 = static_cast<std::uint32_t>((std::uint64_t{magic} * p) >> 32);
  return (t1 + ((p - t1) >> shift1)) >> shift2;
}

PixelDivisor pixel_divisor(std::uint32_t width) {
  if (width == 0) throw Error("pixel_divisor: width 0");
  const int l = width == 1 ? 0 : std::bit_width(width - 1);  // ceil(log2 width)
  PixelDivisor d;
  d.magic = static_cast<std::uint32_t>(((std::uint64_t{1} << 32) * ((std::uint64_t{1} << l) - width)) / width + 1);
  d.shift1 = static_cast<std::uint32_t>(std::min(l, 1));
  d.shift2 = static_cast<std::uint32_t>(std::max(l - 1, 0));
  return d;
}

streams::TuCfg tu_config(const ImageLayout& layout) {
  streams::TuCfg cfg;
  cfg.kd_nodes = layout.kd_nodes.offset;
  cfg.prim_refs = layout.prim_refs.offset;
  cfg.isect_records = layout.isect_records.offset;
  for (int i = 0; i < 3; ++i) {
    cfg.bounds_lo[static_cast<std::size_t>(i)] = std::bit_cast<std::uint32_t>(layout.bounds_lo[i]);
    cfg.bounds_hi[static_cast<std::size_t>(i)] = std::bit_cast<std::uint32_t>(layout.bounds_hi[i]);
  }
  cfg.kd_scale_exponent = static_cast<std::uint32_t>(layout.kd_scale_exponent);  // two's complement
  return cfg;
}

streams::Launch launch_stream(const LaunchFacts& f) {
  if (f.watchdog > 0xffffffffu) {
    throw Error(fmt::format("watchdog {} is past what the RTL's 32-bit count holds (4294967295)", f.watchdog));
  }
  streams::Launch lf;
  lf.pixels = f.width * f.height;
  lf.width = f.width;
  lf.height = f.height;
  lf.spp = f.spp;
  lf.max_depth = f.max_depth;
  lf.raygen = f.raygen;
  lf.code_words = f.code_words;
  lf.image_bytes = f.image_bytes;
  lf.launch_bytes = static_cast<std::uint32_t>(f.launch_block.size());
  lf.data_bytes = f.data_bytes;
  std::memcpy(&lf.shader_count, f.launch_block.data() + mm::kLaunchShaderCountAt, 4);
  std::memcpy(&lf.shader_table, f.launch_block.data() + mm::kLaunchShaderTableAt, 4);
  lf.watchdog = static_cast<std::uint32_t>(f.watchdog);
  const PixelDivisor div = pixel_divisor(lf.width);
  lf.div_magic = div.magic;
  lf.div_shift1 = div.shift1;
  lf.div_shift2 = div.shift2;
  return lf;
}

}  // namespace rpu::sim
