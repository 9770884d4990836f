// libFuzzer target: the assembler on arbitrary text. It may refuse a source only with
// rpu::Error; any other exception, crash, leak or UB is a finding. A source it accepts
// must survive the round trips the tools rely on: firmware_to_text assembles back to
// the same Firmware (what `rpu disasm` promises), and the .rfw bytes load back to it.
//
// Every path the assembler asks for reads as the input itself, so an .include of any
// name exercises include cycles and the nesting limit.
//
// The round trips are skipped for more than 1 MiB of .data (`.space 0x8000000` is
// legitimate and assembles, but copying it four times over under ASan would slow the
// run without testing anything new).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "asm/assembler.hpp"
#include "asm/firmware_file.hpp"
#include "asm/firmware_text.hpp"
#include "common/error.hpp"

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_assembler: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const rpu::isa::SourceLoader input = [&text](const std::filesystem::path&) { return std::optional(text); };
  rpu::isa::Firmware fw;
  try {
    fw = rpu::isa::assemble("fuzz.s", input);
  } catch (const rpu::Error&) {
    return 0;  // the one way to refuse a source
  }
  if (fw.data.size() > (1u << 20)) return 0;

  const std::string listing = rpu::isa::firmware_to_text(fw);
  const rpu::isa::SourceLoader disassembly = [&listing](const std::filesystem::path&) {
    return std::optional(listing);
  };
  try {
    if (rpu::isa::assemble("disassembly.s", disassembly) != fw) {
      finding("the disassembly assembles to a different firmware", listing);
    }
  } catch (const rpu::Error& e) {
    finding("the disassembly does not assemble", std::string(e.what()) + "\n" + listing);
  }
  try {
    if (rpu::isa::firmware_from_bytes(rpu::isa::firmware_to_bytes(fw), "fuzz.rfw") != fw) {
      finding("the .rfw file loads as a different firmware", listing);
    }
  } catch (const rpu::Error& e) {
    finding("the .rfw file of an assembled firmware does not load", e.what());
  }
  return 0;
}
