#pragma once

#include <charconv>
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace rpu {

// A CLI11 check for a count: decimal digits naming a whole number in [min, 2^64 - 1].
// CLI11's own conversion turns a larger number into 2^64 - 1 without a word.
inline CLI::Validator whole_number(const std::string& what, std::uint64_t min) {
  return CLI::Validator(
      [what, min](const std::string& text) {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || error != std::errc() || stop != end || value < min) {
          return fmt::format("{} must be a whole number from {} to {}, got {}", what, min, UINT64_MAX,
                             text.size() > 64 ? text.substr(0, 64) + "..." : text);
        }
        return std::string();
      },
      fmt::format("{}..2^64-1", min));
}

}  // namespace rpu
