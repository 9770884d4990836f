// rpu: the command-line front end of every view of the chip.
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli/progress.hpp"
#include "common/error.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "scene/procedural.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::vector<std::filesystem::path> outputs{"render.png"};
  std::string backend = "reference";
  RenderSettings settings;
};

std::string millions(std::uint64_t n) { return fmt::format("{:.2f} M", static_cast<double>(n) * 1e-6); }

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

int run_scenes() {
  for (const std::string& name : builtin_scene_names()) fmt::print("{}\n", name);
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app{"rpu: a programmable Ray Processing Unit, modelled (reference renderer, golden model)"};
  app.require_subcommand(1);

  RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand("render", "Render a scene to PNG (8-bit sRGB) and/or EXR (linear)");
  render_cmd->add_option("scene", render.scene,
                         "Scene JSON file, built-in scene name (see `rpu scenes`; NAME:SIZE sets the size), "
                         "or a mesh file Assimp reads; none renders the default scene");
  render_cmd->add_option("-o,--output", render.outputs, "Output image(s): .png and/or .exr")
      ->capture_default_str();
  render_cmd->add_option("--backend", render.backend, "Which view of the chip renders")
      ->check(CLI::IsMember({"reference"}))
      ->capture_default_str();
  render_cmd->add_option("--width", render.settings.width, "Image width in pixels")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  render_cmd->add_option("--height", render.settings.height, "Image height in pixels")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  render_cmd->add_option("--spp", render.settings.spp, "Samples per pixel (jittered)")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  render_cmd->add_option("--max-depth", render.settings.max_depth, "Reflection/refraction bounces")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  render_cmd->add_option("--seed", render.settings.seed, "Sample-pattern seed")->capture_default_str();
  render_cmd->add_option("--threads", render.settings.threads, "Host threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();

  CLI::App* scenes_cmd = app.add_subcommand("scenes", "List the built-in scenes");

  CLI11_PARSE(app, argc, argv);
  if (render_cmd->parsed()) return run_render(render);
  if (scenes_cmd->parsed()) return run_scenes();
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
