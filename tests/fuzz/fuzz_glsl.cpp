// libFuzzer target: rpu cc on arbitrary text as a ray generation shader (with an empty
// closest-hit shader). glslang, SPIRV-Tools and the back end may refuse it only with
// rpu::Error; any other exception, crash, leak or UB is a finding. What compiles must
// assemble (compile() assembles it) and fit the registers it was compiled for.
#include <cstddef>
#include <cstdint>
#include <string>

#include "cc/compiler.hpp"
#include "common/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const int level : {0, 2}) {
    rpu::cc::CompileOptions options;
    options.opt_level = level;
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
