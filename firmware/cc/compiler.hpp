// rpu cc: GLSL ray-tracing shaders to one firmware (docs/shaders.md).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "cc/frontend.hpp"
#include "isa/firmware.hpp"

namespace rpu::cc {

// The front end's -O (0: SPIRV-Tools' legalisation passes only; 2: its performance
// passes too), -D, -I and --spec-constant, and the back end's:
struct CompileOptions : FrontEndOptions {
  int registers = 16;    // the firmware uses r0..r(registers-1): 16 runs on every configuration
  bool listing = false;  // also print the firmware as assembly text
};

struct Compiled {
  isa::Firmware firmware;
  std::string listing;  // with CompileOptions::listing: the stack constants, every shader, the trace routines
  std::vector<std::string> warnings;  // "file: ..." each: a specialization constant left at its default
};

struct ShaderSource {
  std::filesystem::path file;  // its extension names the stage; its stem names a hit or miss shader
  std::string text;
};

// One .rgen, any number of .rchit (a material's `shader` name binds to the stem),
// .rmiss (miss index i = the i-th given). Throws rpu::Error with file:line.
Compiled compile(const std::vector<ShaderSource>& sources, const CompileOptions& options);
Compiled compile_files(const std::vector<std::filesystem::path>& files, const CompileOptions& options);

// The firmware for `rpu render --firmware` with shader files: compiled, or read from the
// cache directory (keyed by a hash of the sources, the options and this build), with the
// compile's warnings.
Compiled compile_cached(const std::vector<std::filesystem::path>& files, const CompileOptions& options);

}  // namespace rpu::cc
