#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "isa/firmware.hpp"

// The firmware object file (.rfw): a small little-endian container of a Firmware's
// code words, data bytes, symbol table and line table. docs/assembler.md gives it byte
// by byte.
namespace rpu::isa {

inline constexpr std::uint32_t kFirmwareMagic = 0x31574652;  // "RFW1" read as a little-endian u32
inline constexpr std::uint32_t kFirmwareVersion = 2;  // 2: the line table
inline constexpr std::size_t kFirmwareHeaderBytes = 20;

std::vector<std::uint8_t> firmware_to_bytes(const Firmware& firmware);

// Checks everything (sizes, symbol kinds, names, order and values) and throws
// rpu::Error naming `name` and the byte offset of the first problem.
Firmware firmware_from_bytes(std::span<const std::uint8_t> bytes, const std::string& name);

// Through an OutputFile: a failed write leaves the old file as it was.
void save_firmware(const Firmware& firmware, const std::filesystem::path& file);
Firmware load_firmware(const std::filesystem::path& file);
// By the file's first bytes, not its name: a file that starts with the firmware magic
// is loaded, any other is assembled as source, except that a .rfw without the magic is
// rejected by load_firmware (it names the bytes it found).
Firmware load_firmware_or_assemble(const std::filesystem::path& file);

}  // namespace rpu::isa
