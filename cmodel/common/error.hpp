#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace rpu {

// The one exception type for bad input: the message names the file and line, or
// the address, ray or instruction, and what to do about it (docs/style.md "Errors").
// The CLI prints it as "rpu: error: <message>" and exits with status 1.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// A piece of the user's input (a key, a name, a token) as a message quotes it: whole up
// to 64 bytes, else its first 64 (cut at a UTF-8 character's start) and its length, so
// that a megabyte key cannot fill a terminal.
inline std::string quote_input(std::string_view text) {
  constexpr std::size_t kShown = 64;
  if (text.size() <= kShown) return std::string(text);
  std::size_t cut = kShown;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return std::string(text.substr(0, cut)) + "... (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace rpu
