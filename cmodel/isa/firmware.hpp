#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

// An assembled shader program: what the assembler makes and the device loads.
namespace rpu::isa {

struct Symbol {
  enum class Kind : std::uint8_t { kCode, kData, kConstant };
  Kind kind = Kind::kConstant;
  std::uint32_t value = 0;  // code: instruction index; data: device address; constant: value
  bool operator==(const Symbol&) const = default;
};

struct Firmware {
  std::vector<std::uint64_t> code;  // instruction memory, pc 0 first
  std::vector<std::uint8_t> data;   // loaded at spec::memory::kDeviceDataBase
  std::map<std::string, Symbol, std::less<>> symbols;
  bool operator==(const Firmware&) const = default;
};

}  // namespace rpu::isa
