// rpu: the command-line front end of every view of the chip.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "common/error.hpp"

namespace rpu::cli {
namespace {

int run(int argc, char** argv) {
  record_invocation(argc, argv);
  CLI::App app{"rpu: a programmable Ray Processing Unit, modelled (reference renderer, golden model)"};
  app.require_subcommand(1);
  const Command commands[] = {add_render_command(app), add_raycast_command(app), add_tree_command(app),
                              add_scenes_command(app), add_asm_command(app), add_disasm_command(app), add_cc_command(app),
                              add_config_command(app), add_accel_command(app),
                              add_sweep_command(app), add_sweep_point_command(app), add_report_command(app),
                              add_fit_command(app)};
  CLI11_PARSE(app, argc, argv);
  for (const Command& command : commands) {
    if (command.subcommand->parsed()) {
      note_command_line_files(*command.subcommand);
      return command.run();
    }
  }
  return 1;
}

}  // namespace

namespace {
Invocation the_invocation;
}  // namespace

std::string shell_word(std::string_view arg) {
  const bool safe = !arg.empty() && std::all_of(arg.begin(), arg.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::string_view("@%+=:,./-_").find(c) != std::string_view::npos;
  });
  if (safe) return std::string(arg);
  std::string out = "'";
  for (const char c : arg) out += c == '\'' ? std::string("'\"'\"'") : std::string(1, c);
  return out + "'";
}

void record_invocation(int argc, const char* const* argv) {
  the_invocation.start = std::chrono::steady_clock::now();
  the_invocation.command_line.clear();
  for (int i = 0; i < argc; ++i) the_invocation.command_line += (i ? " " : "") + shell_word(argv[i]);
}

const Invocation& invocation() { return the_invocation; }

}  // namespace rpu::cli

int main(int argc, char** argv) {
  try {
    return rpu::cli::run(argc, argv);
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "rpu: error: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the user gave that a check before it did not foresee: still theirs, named.
    std::fprintf(stderr, "rpu: error: %s: %s\n", e.path1().c_str(), e.code().message().c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "rpu: error: out of memory: the host refused an allocation (a limit such as ulimit -v?)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rpu: internal error: %s\n", e.what());
    return 2;
  }
}
