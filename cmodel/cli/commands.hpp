#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace rpu::cli {

// Each subcommand adds itself and its options to the app and returns the function that
// runs it once parsing is done (exit status). Errors are thrown as rpu::Error.
struct Command {
  CLI::App* subcommand;
  std::function<int()> run;
};

// How the tool was started, for the records a run writes (rpu render --stats).
struct Invocation {
  std::string command_line;  // the arguments, quoted for a POSIX shell where they need it
  std::chrono::steady_clock::time_point start;
};
void record_invocation(int argc, const char* const* argv);

// A POSIX shell word: as it is when made of safe characters only (shlex.quote's set),
// else in single quotes, each ' written '"'"'. For command lines a shell reads back.
std::string shell_word(std::string_view arg);
const Invocation& invocation();

Command add_render_command(CLI::App& app);
Command add_raycast_command(CLI::App& app);
Command add_tree_command(CLI::App& app);
Command add_scenes_command(CLI::App& app);
Command add_asm_command(CLI::App& app);
Command add_disasm_command(CLI::App& app);
Command add_cc_command(CLI::App& app);
Command add_config_command(CLI::App& app);
Command add_accel_command(CLI::App& app);
Command add_sweep_command(CLI::App& app);
Command add_sweep_point_command(CLI::App& app);
Command add_report_command(CLI::App& app);
Command add_fit_command(CLI::App& app);

}  // namespace rpu::cli
