// libFuzzer target: rpu cc on arbitrary text as a ray generation shader (with an empty
// closest-hit shader). glslang, SPIRV-Tools and the back end may refuse it only with
// rpu::Error; any other exception, crash, leak or UB is a finding. What compiles must fit
// the registers it was compiled for and keep its spills' pushes and pops paired
// (regalloc.cpp checks), and its listing must assemble to the firmware compile() encoded.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "asm/assembler.hpp"
#include "cc/compiler.hpp"
#include "common/error.hpp"

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_glsl: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // -O0, -O2, and -O2 in the fewest registers the calling convention allows (spills)
  for (const auto& [level, registers] : {std::pair{0, 16}, std::pair{2, 16}, std::pair{2, 6}}) {
    rpu::cc::CompileOptions options;
    options.opt_level = level;
    options.registers = registers;
    options.listing = true;
    rpu::cc::Compiled compiled;
    try {
      compiled = rpu::cc::compile(
          {{"fuzz.rgen", text},
           {"whitted.rchit", "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n"}},
          options);
    } catch (const rpu::Error&) {
      continue;  // refused with a message: fine
    }
    const rpu::isa::SourceLoader listing = [&compiled](const std::filesystem::path&) {
      return std::optional(compiled.listing);
    };
    try {
      if (rpu::isa::assemble("listing.s", listing) != compiled.firmware) {
        finding("the listing assembles to a different firmware", compiled.listing);
      }
    } catch (const rpu::Error& e) {
      finding("the listing does not assemble", std::string(e.what()) + "\n" + compiled.listing);
    }
  }
  return 0;
}
