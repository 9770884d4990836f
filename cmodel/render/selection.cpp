#include "render/selection.hpp"

#include <charconv>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu {

namespace mm = spec::memory;

namespace {

std::vector<std::string_view> split(std::string_view text, char at) {
  std::vector<std::string_view> parts;
  for (std::size_t from = 0;;) {
    const std::size_t to = text.find(at, from);
    parts.push_back(text.substr(from, to == std::string_view::npos ? std::string_view::npos : to - from));
    if (to == std::string_view::npos) return parts;
    from = to + 1;
  }
}

}  // namespace

Selection parse_selection(std::string_view text) {
  const auto bad = [&](std::string_view why) {
    return Error(fmt::format("selection '{}': {} (the form is BLOCK[:THRESHOLD[:material|primitive]], "
                             "for example 4:0.05:material; docs/selection.md)",
                             text, why));
  };
  const std::vector<std::string_view> parts = split(text, ':');
  if (parts.size() > 3) throw bad("more than three parts");
  Selection s;
  const std::string_view block = parts[0];
  const auto [end, ec] = std::from_chars(block.data(), block.data() + block.size(), s.block);
  if (ec != std::errc{} || end != block.data() + block.size()) throw bad(fmt::format("block '{}' is not a whole number", block));
  if (s.block < 1 || s.block > static_cast<int>(mm::kSelectMaxBlock)) {
    throw bad(fmt::format("block {} is outside 1..{}", s.block, mm::kSelectMaxBlock));
  }
  if (parts.size() > 1) {
    const std::string_view threshold = parts[1];
    const auto [tend, tec] = std::from_chars(threshold.data(), threshold.data() + threshold.size(), s.threshold);
    if (threshold.empty() || tec != std::errc{} || tend != threshold.data() + threshold.size() ||
        !std::isfinite(s.threshold)) {
      throw bad(fmt::format("threshold '{}' is not a finite number", threshold));
    }
  }
  if (parts.size() > 2) {
    if (parts[2] == "material") {
      s.key = mm::kSelectKeyMaterial;
    } else if (parts[2] == "primitive") {
      s.key = mm::kSelectKeyPrimitive;
    } else {
      throw bad(fmt::format("key '{}' is neither material nor primitive", parts[2]));
    }
  }
  return s;
}

std::string to_string(const Selection& s) {
  if (!s.enabled()) return "1";
  return fmt::format("{}:{}:{}", s.block, s.threshold, s.key == mm::kSelectKeyPrimitive ? "primitive" : "material");
}

}  // namespace rpu
