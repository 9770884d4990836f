// libFuzzer target: rpu cc on arbitrary text as a ray generation shader (with an empty
// closest-hit shader). glslang, SPIRV-Tools and the back end may refuse it only with
// rpu::Error; any other exception, crash, leak or UB is a finding. What compiles must
// assemble (compile() assembles it), fit the registers it was compiled for and keep its
// spills' pushes and pops paired (regalloc.cpp checks).
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "cc/compiler.hpp"
#include "common/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // -O0, -O2, and -O2 in the fewest registers the calling convention allows (spills)
  for (const auto& [level, registers] : {std::pair{0, 16}, std::pair{2, 16}, std::pair{2, 6}}) {
    rpu::cc::CompileOptions options;
    options.opt_level = level;
    options.registers = registers;
    try {
      rpu::cc::compile({{"fuzz.rgen", text},
                        {"whitted.rchit", "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n"}},
                       options);
    } catch (const rpu::Error&) {
      // refused with a message: fine
    }
  }
  return 0;
}
