// rpu render: a scene to PNG/EXR through one view of the chip.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "device/builtin_firmware.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::vector<std::filesystem::path> outputs{"render.png"};
  std::string backend = "reference";
  std::filesystem::path firmware;  // empty: the built-in whitted.s
  RenderSettings settings;
  ChipOptions chip;
};

// The reference renderer: double precision, no ISA. Returns the rays by type.
Image render_reference(const Scene& scene, const RenderSettings& settings, RayCounts& counts) {
  const ReferenceRenderer renderer(scene);
  ProgressBar bar(fmt::format("rendering {}", scene.source));
  return renderer.render(settings, &counts, [&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
}

// The golden model: firmware on the functional shader cores, traversal and
// intersection units, in the configured number format.
Image render_functional(const Scene& scene, const RenderOptions& o, std::string& summary) {
  const KdBuildConfig build = o.chip.build_config();
  const functional::SceneImage si = functional::make_scene_image(scene, build, o.chip.isect_mode());
  const isa::Firmware firmware =
      o.firmware.empty() ? device::builtin_firmware("whitted.s") : device::load_firmware_file(o.firmware);
  device::FunctionalOptions options;
  options.host_threads = o.settings.threads;
  const auto dev = device::make_functional_device(o.chip.hardware_config(), build.format, options);
  Image image;
  {
    ProgressBar bar(fmt::format("rendering {} (functional, {}, {})", scene.source, o.chip.config,
                                build.format.name()));
    image = device::render_frame(*dev, scene, si.image, firmware, o.settings,
                                 [&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
  }
  const device::DeviceStats st = dev->stats();
  const functional::ShaderStats& sh = st.shader;
  std::string classes;
  for (std::size_t i = 0; i < sh.retired.size(); ++i) {
    classes += fmt::format("{}{} {}", i ? ", " : "", spec::isa::kClassNames[i], millions(sh.retired[i]));
  }
  summary = fmt::format("{} instructions ({}), SIMD efficiency {:.1f}% (chunk {}); {} rays ({} closest-hit, {} any-hit); "
                        "traversal {} nodes, {} leaves, {} triangle tests",
                        millions(sh.instructions()), classes,
                        100.0 * static_cast<double>(sh.instructions()) / static_cast<double>(std::max<std::uint64_t>(1, sh.lanes_issued)),
                        o.chip.hardware_config().chunk_size, millions(sh.closest_rays + sh.any_rays),
                        millions(sh.closest_rays), millions(sh.any_rays), millions(sh.nodes), millions(sh.leaves),
                        millions(sh.tests));
  return image;
}

int run_render(const RenderOptions& options) {
  for (const std::filesystem::path& out : options.outputs) check_image_extension(out);
  const Scene scene = resolve_scene(options.scene);
  for (const std::string& warning : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", warning);

  const auto start = std::chrono::steady_clock::now();
  RayCounts counts;
  std::string device_summary;
  const Image image = options.backend == "reference" ? render_reference(scene, options.settings, counts)
                                                     : render_functional(scene, options, device_summary);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<std::string> written;
  for (const std::filesystem::path& out : options.outputs) {
    write_image(image, out);
    written.push_back(out.string());
  }
  const RenderSettings& s = options.settings;
  if (!device_summary.empty()) {
    fmt::print(stderr, "rpu: {} {}x{}, {} spp, max depth {}, {} backend, {} triangles: {} in {:.2f} s -> {}\n",
               scene.source, s.width, s.height, s.spp, s.max_depth, options.backend, scene.triangles.size(),
               device_summary, seconds, fmt::join(written, ", "));
    return 0;
  }
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
      ->check(CLI::IsMember({"reference", "functional"}))
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

  render_cmd->add_option("--firmware", render->firmware,
                         "functional backend: firmware (.s or .rfw) instead of the built-in whitted.s");
  add_chip_options(*render_cmd, render->chip);

  return {render_cmd, [render] { return run_render(*render); }};
}

}  // namespace rpu::cli
