// rpu tree: build the kd-tree of a scene and print its statistics.
#include <memory>
#include <string>

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
            const KdBuildConfig build = o->chip.build_config();
            const KdTree tree = build_kdtree(scene, build);
            fmt::print("{}: {} triangles\n{}\n", scene.source, scene.triangles.size(), format_kd_stats(tree.stats));
            if (build.format != fp::kFp32) {
              KdBuildConfig fp32 = build;
              fp32.format = fp::kFp32;
              const std::string note =
                  lost_planes_note(fp::format_label(build.format), tree.stats, build_kdtree(scene, fp32).stats);
              if (!note.empty()) fmt::print("note: {}\n", note);
            }
            return 0;
          }};
}

}  // namespace rpu::cli
