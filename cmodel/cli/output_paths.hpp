#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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
// writable directory (check_output_path). The inputs are `inputs` (files a command
// finds itself: an included source) and every file named on the command line by an
// option or argument that is not one of `outputs`' (note_command_line_files), so no
// command can forget one.
void check_outputs(const std::vector<PlannedOutput>& outputs, const std::vector<PlannedInput>& inputs);

// Keeps the regular files the values of `command`'s given options and arguments name
// (and its parsed subcommands'), for check_outputs. Called once parsing is done.
void note_command_line_files(const CLI::App& command);

}  // namespace rpu::cli
