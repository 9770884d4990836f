#include "asm/builtin_firmware.hpp"

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/builtin_firmware_sources.hpp"
#include "common/error.hpp"

namespace rpu::isa {

std::optional<std::string> builtin_firmware_source(const std::filesystem::path& file) {
  for (const auto& [name, text] : kBuiltinFirmwareSources) {
    if (file == name) return std::string(text);
  }
  return std::nullopt;
}

Firmware builtin_firmware(std::string_view file) {
  if (!builtin_firmware_source(file)) throw Error(fmt::format("no built-in firmware '{}'", file));
  return assemble(file, builtin_firmware_source);
}

}  // namespace rpu::isa
