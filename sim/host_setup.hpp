#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "memory/memory_image.hpp"
#include "rpu/streams.hpp"

// What the host hands the chip before a frame, from the same facts the functional
// backend reads (docs/chip.md): the traversal units' view of the scene and the
// shader cores' launch. Shared by the co-simulation harnesses and the rtl backend.
namespace rpu::sim {

// x and y of a pixel index p by multiplication, as the core computes them for `rdsr
// pixel` (Granlund and Montgomery 1994, "Division by invariant integers using
// multiplication", fig. 4.1): q = (t1 + ((p - t1) >> shift1)) >> shift2 with
// t1 = (magic * p) >> 32, for every 32-bit p.
struct PixelDivisor {
  std::uint32_t magic = 0, shift1 = 0, shift2 = 0;
  std::uint32_t quotient(std::uint32_t p) const;
};
PixelDivisor pixel_divisor(std::uint32_t width);

// Where the traversal units find the scene (the image's layout).
streams::TuCfg tu_config(const ImageLayout& layout);

struct LaunchFacts {
  std::uint32_t width = 1, height = 1, spp = 1, max_depth = 0;
  std::uint32_t raygen = 0;          // the firmware's raygen label
  std::uint32_t code_words = 0;      // its instructions
  std::uint32_t image_bytes = 0;
  std::span<const std::uint8_t> launch_block;  // with the shader table after it
  std::uint32_t data_bytes = 0;      // the firmware's .data
  std::uint64_t watchdog = 0;        // rpu::Error past 2^32 - 1, the RTL's counter
};
streams::Launch launch_stream(const LaunchFacts& facts);

// After reset: the firmware's words into the code memories, one a cycle, then start for
// one cycle; the cycle after it, the frame's first, is returned. `Clock` is a harness
// clock (cosim_core.hpp) over a shader core or the chip, `in` its inputs with the launch
// already set.
template <class Clock, class Inputs>
std::uint64_t write_code_and_start(Clock& clock, Inputs& in, const std::vector<std::uint64_t>& code) {
  for (std::uint32_t pc = 0; pc < code.size(); ++pc) {
    in.code_we = true;
    in.code_addr = pc;
    in.code_data = code[pc];
    clock.settle(in);
    clock.tick();
  }
  in.code_we = false;
  in.start = true;
  clock.settle(in);
  clock.tick();
  in.start = false;
  return clock.cycle();
}

}  // namespace rpu::sim
