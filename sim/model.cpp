#include "model.hpp"

#include <charconv>

#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu::sim {

std::string_view ModelInfo::fact(std::string_view key) const {
  std::string_view rest = facts_;
  while (!rest.empty()) {
    const std::size_t end = rest.find(' ');
    const std::string_view word = rest.substr(0, end);
    if (word.size() > key.size() && word.substr(0, key.size()) == key && word[key.size()] == '=') {
      return word.substr(key.size() + 1);
    }
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
  }
  return {};
}

int ModelInfo::number(std::string_view key) const {
  const std::string_view text = fact(key);
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    throw Error(fmt::format("model {} has no number '{}' among its facts ({})", name_, key, facts_));
  }
  return value;
}

bool ModelInfo::matches(std::initializer_list<std::pair<std::string_view, std::string_view>> wanted) const {
  for (const auto& [key, value] : wanted) {
    if (fact(key) != value) return false;
  }
  return true;
}

}  // namespace rpu::sim
