#pragma once

#include <stdexcept>
#include <string>

namespace rpu {

// The one exception type for bad input: the message names the file and line, or
// the address, ray or instruction, and what to do about it (docs/style.md "Errors").
// The CLI prints it as "rpu: error: <message>" and exits with status 1.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace rpu
