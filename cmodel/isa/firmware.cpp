#include "isa/firmware.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace rpu::isa {

void LineTable::add(std::uint32_t pc, std::string_view file, std::uint32_t line) {
  SourceLine source;
  if (line != 0) {
    const auto known = std::find(files.begin(), files.end(), file);
    source = {static_cast<std::uint32_t>(known - files.begin()), line};
    if (known == files.end()) files.emplace_back(file);
  }
  if (runs.empty() ? line != 0 : runs.back().source != source) runs.push_back({pc, source});
}

std::optional<std::string> LineTable::where(std::uint32_t pc) const {
  const auto after = std::upper_bound(runs.begin(), runs.end(), pc, [](std::uint32_t p, const Run& r) { return p < r.pc; });
  if (after == runs.begin() || std::prev(after)->source.line == 0) return std::nullopt;
  const SourceLine& s = std::prev(after)->source;
  return fmt::format("{}:{}", files[s.file], s.line);
}

}  // namespace rpu::isa
