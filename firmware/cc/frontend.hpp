// The compiler's front end: GLSL ray-tracing shaders to validated, optimised SPIR-V
// through glslang and SPIRV-Tools.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rpu::cc {

enum class Stage { kRaygen, kClosestHit, kMiss, kAnyHit };

// The stage a file's extension names (.rgen, .rchit, .rmiss, .rahit); throws rpu::Error otherwise.
Stage stage_of(const std::filesystem::path& file);
const char* stage_name(Stage stage);

struct SpirvShader {
  std::filesystem::path file;
  Stage stage = Stage::kRaygen;
  std::vector<std::uint32_t> words;
};

// Compiles one shader. `source` is the file's text; #include "x" looks beside the
// including file, then in the shader library (firmware/glsl/ and the generated
// rpu_memory.glsl, built into the binary). opt_level 0 runs SPIRV-Tools' legalisation
// passes (inlining, scalar replacement, SSA: what the back end needs), 2 its
// performance passes as well. Throws rpu::Error with glslang's file:line messages, or
// SPIRV-Tools' message if the optimised module does not validate.
SpirvShader compile_glsl(const std::filesystem::path& file, const std::string& source, int opt_level);

// The source after the preprocessor (includes expanded); throws rpu::Error like compile_glsl.
std::string preprocess_glsl(const std::filesystem::path& file, const std::string& source);

// The library's text of one header, if it has one by that name (rpu.glsl, rpu_memory.glsl, ...).
const std::string* library_header(const std::string& name);

}  // namespace rpu::cc
