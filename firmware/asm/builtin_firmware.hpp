#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "isa/firmware.hpp"

namespace rpu::isa {

// The firmware sources of firmware/*.s, built into the binary so that `rpu render`
// needs no source tree. Paths are the file names ("whitted.s").
std::optional<std::string> builtin_firmware_source(const std::filesystem::path& file);

// Assembles a built-in firmware file, e.g. "whitted.s".
Firmware builtin_firmware(std::string_view file);

}  // namespace rpu::isa
