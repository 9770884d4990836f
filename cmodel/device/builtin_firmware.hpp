#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "isa/firmware.hpp"

namespace rpu::device {

// The firmware sources of firmware/*.s, built into the binary so that `rpu render`
// needs no source tree. Paths are the file names ("whitted.s").
std::optional<std::string> builtin_firmware_source(const std::filesystem::path& file);

// Assembles a built-in firmware file, e.g. "whitted.s".
isa::Firmware builtin_firmware(std::string_view file);

// A firmware file given by the user: assembled firmware (by its magic) or a source.
isa::Firmware load_firmware_file(const std::filesystem::path& file);

}  // namespace rpu::device
