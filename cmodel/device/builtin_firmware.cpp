#include "device/builtin_firmware.hpp"

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/firmware_file.hpp"
#include "common/error.hpp"
#include "device/builtin_firmware_sources.hpp"

namespace rpu::device {

std::optional<std::string> builtin_firmware_source(const std::filesystem::path& file) {
  for (const auto& [name, text] : kBuiltinFirmwareSources) {
    if (file == name) return std::string(text);
  }
  return std::nullopt;
}

isa::Firmware builtin_firmware(std::string_view file) {
  if (!builtin_firmware_source(file)) throw Error(fmt::format("no built-in firmware '{}'", file));
  return isa::assemble(file, builtin_firmware_source);
}

isa::Firmware load_firmware_file(const std::filesystem::path& file) { return isa::load_firmware_or_assemble(file); }

}  // namespace rpu::device
