#pragma once

#include <string>
#include <string_view>

namespace rpu {

// One CSV field (RFC 4180): a field with a comma, a quote or a line break is quoted, its
// quotes doubled; `always_quote` quotes it anyway (text beside numbers in a row).
inline std::string csv_field(std::string_view text, bool always_quote = false) {
  if (!always_quote && text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + '"';
}

}  // namespace rpu
