#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// An assembled shader program: what the assembler makes and the device loads.
namespace rpu::isa {

struct Symbol {
  enum class Kind : std::uint8_t { kCode, kData, kConstant };
  Kind kind = Kind::kConstant;
  std::uint32_t value = 0;  // code: instruction index; data: device address; constant: value
  bool operator==(const Symbol&) const = default;
};

// A source line: a file of LineTable::files and a line in it; line 0 is none (code a
// compiler made for no line of its source).
struct SourceLine {
  std::uint32_t file = 0;
  std::uint32_t line = 0;
  bool operator==(const SourceLine&) const = default;
};

// Where each instruction came from, so that a fault names the line of assembly or GLSL
// it happened on: runs of pcs, each run from its pc to the next run's with one source
// line. Canonical, so that equal tables are equal: runs in ascending pc, each with
// another line than the run before; files in the order the runs first name them, each
// named; a run of no line has file 0.
struct LineTable {
  struct Run {
    std::uint32_t pc = 0;
    SourceLine source;
    bool operator==(const Run&) const = default;
  };
  static constexpr std::uint32_t kMaxFileName = 4096;  // bytes; no control characters
  std::vector<std::string> files;
  std::vector<Run> runs;

  // Appends pc's line; pcs come in ascending order.
  void add(std::uint32_t pc, std::string_view file, std::uint32_t line);
  // "file:line" of the instruction at pc, or nullopt if it has no line.
  std::optional<std::string> where(std::uint32_t pc) const;
  bool operator==(const LineTable&) const = default;
};

struct Firmware {
  std::vector<std::uint64_t> code;  // instruction memory, pc 0 first
  std::vector<std::uint8_t> data;   // loaded at spec::memory::kDeviceDataBase
  std::map<std::string, Symbol, std::less<>> symbols;
  LineTable lines;
  bool operator==(const Firmware&) const = default;
};

}  // namespace rpu::isa
