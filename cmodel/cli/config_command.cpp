// rpu config: hardware configurations (docs/configurations.md).
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.hpp"
#include "config/config.hpp"
#include "rpu/spec.hpp"

namespace rpu::cli {
namespace {

struct ConfigShowOptions {
  std::string config = "default";
  std::vector<std::string> sets;
};

}  // namespace

Command add_config_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("config", "Hardware configurations: list the named ones, show one resolved");
  cmd->require_subcommand(0, 1);
  CLI::App* list = cmd->add_subcommand("list", "The named configurations (spec/configs.toml)");
  CLI::App* show = cmd->add_subcommand("show", "Print a configuration, resolved, as TOML that --config reads back");
  auto o = std::make_shared<ConfigShowOptions>();
  show->add_option("config", o->config, "A named configuration or a TOML file")->capture_default_str();
  show->add_option("--set", o->sets, "Change one key, e.g. --set shader_cores=8 (repeatable)")->type_name("KEY=VALUE");
  return {cmd, [list, show, o] {
            if (list->parsed() || !show->parsed()) {
              for (const spec::HardwareConfig& c : spec::kConfigs) fmt::print("{:10} {}\n", c.name, c.doc);
              if (!list->parsed()) fmt::print("\n`rpu config show NAME|FILE.toml [--set key=value]` prints one.\n");
              return 0;
            }
            fmt::print("{}", config::to_toml(config::resolve(o->config, o->sets)));
            return 0;
          }};
}

}  // namespace rpu::cli
