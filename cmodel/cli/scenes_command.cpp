// rpu scenes: the built-in scene generators.
#include <fmt/format.h>

#include "cli/commands.hpp"
#include "scene/procedural.hpp"

namespace rpu::cli {

Command add_scenes_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("scenes", "List the built-in scenes (use NAME or NAME:SIZE as SCENE)");
  return {cmd, [] {
            for (const std::string& name : builtin_scene_names()) fmt::print("{}\n", name);
            return 0;
          }};
}

}  // namespace rpu::cli
