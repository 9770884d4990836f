// rpu: the command-line front end of every view of the chip.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "common/error.hpp"

namespace rpu::cli {
namespace {

int run(int argc, char** argv) {
  CLI::App app{"rpu: a programmable Ray Processing Unit, modelled (reference renderer, golden model)"};
  app.require_subcommand(1);
  const Command commands[] = {add_render_command(app), add_raycast_command(app), add_tree_command(app),
                              add_scenes_command(app), add_asm_command(app), add_disasm_command(app),
                              add_config_command(app)};
  CLI11_PARSE(app, argc, argv);
  for (const Command& command : commands) {
    if (command.subcommand->parsed()) return command.run();
  }
  return 1;
}

}  // namespace
}  // namespace rpu::cli

int main(int argc, char** argv) {
  try {
    return rpu::cli::run(argc, argv);
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "rpu: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rpu: internal error: %s\n", e.what());
    return 2;
  }
}
