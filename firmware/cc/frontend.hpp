// The compiler's front end: GLSL ray-tracing shaders to validated, optimised SPIR-V
// through glslang and SPIRV-Tools.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace rpu::cc {

enum class Stage { kRaygen, kClosestHit, kMiss, kAnyHit };

// The stage a file's extension names (.rgen, .rchit, .rmiss, .rahit); throws rpu::Error otherwise.
Stage stage_of(const std::filesystem::path& file);
const char* stage_name(Stage stage);

// What every shader of a compile is compiled with: rpu cc's -O, -D, -I and --spec-constant.
struct FrontEndOptions {
  int opt_level = 2;
  std::vector<std::string> defines;                     // NAME or NAME=VALUE: #define NAME VALUE
  std::vector<std::filesystem::path> include_dirs;      // searched after the including file's directory
  std::map<std::uint32_t, std::string> spec_constants;  // constant_id -> value, as written
};

// A specialization constant a shader declares: layout(constant_id = N) const T NAME = D.
struct SpecConstant {
  std::uint32_t id = 0;
  std::string name;
  std::string type;         // bool, int, uint or float
  std::string value;        // the value compiled in, as GLSL writes it
  bool given = false;       // from FrontEndOptions::spec_constants, else the default
};

struct SpirvShader {
  std::filesystem::path file;
  Stage stage = Stage::kRaygen;
  std::vector<std::uint32_t> words;
  std::vector<SpecConstant> spec_constants;
};

// Checks a -D and a --spec-constant as given; throws rpu::Error saying what is wrong.
void check_define(const std::string& define);
std::pair<std::uint32_t, std::string> parse_spec_constant(const std::string& assignment);

// Compiles one shader. `source` is the file's text; #include "x" looks beside the
// including file, then in the include directories, then in the shader library
// (firmware/glsl/ and the generated rpu_memory.glsl, built into the binary). opt_level 0
// runs SPIRV-Tools' legalisation passes (inlining, scalar replacement, SSA: what the
// back end needs), 2 its performance passes as well. The shader's specialization
// constants get the values given for their ids (a value that is not of the constant's
// type is an error), the others keep their defaults. Throws rpu::Error with glslang's
// file:line messages, or SPIRV-Tools' message if the optimised module does not validate.
SpirvShader compile_glsl(const std::filesystem::path& file, const std::string& source, const FrontEndOptions& options);

// The source after the preprocessor (includes expanded, defines applied); throws
// rpu::Error like compile_glsl.
std::string preprocess_glsl(const std::filesystem::path& file, const std::string& source,
                            const FrontEndOptions& options);

// The library's text of one header, if it has one by that name (rpu.glsl, rpu_memory.glsl, ...).
const std::string* library_header(const std::string& name);

}  // namespace rpu::cc
