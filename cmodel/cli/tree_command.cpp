// rpu tree: build the kd-tree of a scene and print its statistics.
#include <memory>

#include <fmt/format.h>

#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {

Command add_tree_command(CLI::App& app) {
  struct Options {
    std::string scene;
    ChipOptions chip;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("tree", "Build a scene's SAH kd-tree and print its statistics");
  cmd->add_option("scene", o->scene, "Scene file, built-in name or mesh file (default: the Cornell box)");
  add_chip_options(*cmd, o->chip);
  return {cmd, [o] {
            const Scene scene = resolve_scene(o->scene);
            for (const std::string& w : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
            const KdTree tree = build_kdtree(scene, o->chip.build_config());
            fmt::print("{}: {} triangles\n{}\n", scene.source, scene.triangles.size(), format_kd_stats(tree.stats));
            return 0;
          }};
}

}  // namespace rpu::cli
