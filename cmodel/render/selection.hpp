#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "rpu/spec.hpp"

namespace rpu {

// Selected ray tracing (docs/selection.md): the firmware traces the corners of B x B
// blocks and interpolates each block whose corners agree, tracing every pixel of one
// whose corners disagree. block 1 traces every pixel.
struct Selection {
  int block = 1;
  float threshold = 0.05f;  // per channel, linear RGB: corners further apart disagree
  std::uint32_t key = spec::memory::kSelectKeyMaterial;  // a spec select_key

  bool enabled() const { return block > 1; }
};

// "B", "B:THRESHOLD" or "B:THRESHOLD:material|primitive" (the form --select and a sweep's
// select axis take); rpu::Error saying what is wrong with `text`.
Selection parse_selection(std::string_view text);
// The form parse_selection reads back: "1" when off, else all three parts.
std::string to_string(const Selection& selection);

}  // namespace rpu
