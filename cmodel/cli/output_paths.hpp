#pragma once

#include <filesystem>
#include <string>
#include <vector>

// The files a command will write, checked before it starts the work, so that a bad
// --stats path does not cost the user the whole render.
namespace rpu::cli {

struct PlannedOutput {
  std::string option;  // as the user typed it: "-o", "--stats"
  std::filesystem::path path;
  std::vector<std::string> extensions;  // the ones the writer knows; empty: any
};

struct PlannedInput {
  std::string what;  // "the scene file", "the assembly source"
  std::filesystem::path path;
};

// Throws rpu::Error naming the option and path unless no output is the same file as
// an input or as another output, and every output has a known extension and a
// writable directory (check_output_path).
void check_outputs(const std::vector<PlannedOutput>& outputs, const std::vector<PlannedInput>& inputs);

}  // namespace rpu::cli
