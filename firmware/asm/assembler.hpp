#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "isa/firmware.hpp"

// The shader assembler: RPU assembly text (docs/assembler.md) to a Firmware. The
// syntax of instructions is exactly what rpu::isa::disassemble prints, so every
// disassembled word assembles back to itself.
namespace rpu::isa {

// Returns the text of a source file, or nullopt if there is none. Paths are as the
// assembler forms them: the main file as given, an .include relative to the
// directory of the file that includes it (lexically normalised).
using SourceLoader = std::function<std::optional<std::string>(const std::filesystem::path&)>;

// Where a statement came from, for the listing.
struct ListingLine {
  bool code = true;            // an instruction (pc) or a data directive (device address)
  std::uint32_t address = 0;   // pc, or the device address of the first byte
  std::uint32_t bytes = 0;     // data only: how many bytes the directive made
  std::string file;
  int line = 0;
  std::string text;  // the source line, without trailing blanks
};

struct Assembly {
  Firmware firmware;
  std::vector<ListingLine> listing;  // in source order
};

// Assemble `file` (and what it includes). Every problem is an rpu::Error whose
// message holds one "file:line:col: error: ..." line per error (at most 20).
Firmware assemble(const std::filesystem::path& file);
Firmware assemble(const std::filesystem::path& file, const SourceLoader& load);
Assembly assemble_with_listing(const std::filesystem::path& file, const SourceLoader& load);

// Reads files from disk: the loader the file-only overload uses.
std::optional<std::string> read_source_file(const std::filesystem::path& file);

// The listing text: "pc  word  file:line  source" per instruction and
// "address  (n bytes)  file:line  source" per data directive.
std::string format_listing(const Assembly& assembly);

// True if `name` may name a symbol: an identifier [A-Za-z_.][A-Za-z0-9_.]* that is not
// a register name (r<digits>...).
bool is_symbol_name(std::string_view name);

}  // namespace rpu::isa
