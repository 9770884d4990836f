#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace rpu::cli {

// Each subcommand adds itself and its options to the app and returns the function that
// runs it once parsing is done (exit status). Errors are thrown as rpu::Error.
struct Command {
  CLI::App* subcommand;
  std::function<int()> run;
};

Command add_render_command(CLI::App& app);
Command add_raycast_command(CLI::App& app);
Command add_tree_command(CLI::App& app);
Command add_scenes_command(CLI::App& app);
Command add_asm_command(CLI::App& app);
Command add_disasm_command(CLI::App& app);
Command add_config_command(CLI::App& app);

}  // namespace rpu::cli
