// rpu render: a scene to PNG/EXR through one view of the chip.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::vector<std::filesystem::path> outputs{"render.png"};
  std::string backend = "reference";
  RenderSettings settings;
};

int run_render(const RenderOptions& options) {
  for (const std::filesystem::path& out : options.outputs) check_image_extension(out);
  const Scene scene = resolve_scene(options.scene);
  for (const std::string& warning : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", warning);

  const auto start = std::chrono::steady_clock::now();
  const ReferenceRenderer renderer(scene);
  RayCounts counts;
  Image image;
  {
    ProgressBar bar(fmt::format("rendering {}", scene.source));
    image = renderer.render(options.settings, &counts,
                            [&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<std::string> written;
  for (const std::filesystem::path& out : options.outputs) {
    write_image(image, out);
    written.push_back(out.string());
  }
  const RenderSettings& s = options.settings;
  fmt::print(stderr,
             "rpu: {} {}x{}, {} spp, max depth {}, {} backend, {} triangles: {} rays ({} primary, {} shadow, "
             "{} reflection, {} refraction) in {:.2f} s, {:.2f} M rays/s -> {}\n",
             scene.source, s.width, s.height, s.spp, s.max_depth, options.backend, scene.triangles.size(),
             millions(counts.total()), millions(counts.primary), millions(counts.shadow),
             millions(counts.reflection), millions(counts.refraction), seconds,
             static_cast<double>(counts.total()) * 1e-6 / seconds, fmt::join(written, ", "));
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) {
  auto render = std::make_shared<RenderOptions>();
  CLI::App* render_cmd = app.add_subcommand("render", "Render a scene to PNG (8-bit sRGB) and/or EXR (linear)");
  render_cmd->add_option("scene", render->scene,
                         "Scene JSON file, built-in scene name (see `rpu scenes`; NAME:SIZE sets the size), "
                         "or a mesh file Assimp reads; none renders the default scene");
  render_cmd->add_option("-o,--output", render->outputs, "Output image(s): .png and/or .exr")
      ->capture_default_str();
  render_cmd->add_option("--backend", render->backend, "Which view of the chip renders")
      ->check(CLI::IsMember({"reference"}))
      ->capture_default_str();
  render_cmd->add_option("--width", render->settings.width, "Image width in pixels")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  render_cmd->add_option("--height", render->settings.height, "Image height in pixels")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  render_cmd->add_option("--spp", render->settings.spp, "Samples per pixel (jittered)")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  render_cmd->add_option("--max-depth", render->settings.max_depth, "Reflection/refraction bounces")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  render_cmd->add_option("--seed", render->settings.seed, "Sample-pattern seed")->capture_default_str();
  render_cmd->add_option("--threads", render->settings.threads, "Host threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();

  return {render_cmd, [render] { return run_render(*render); }};
}

}  // namespace rpu::cli
