// rpu render: a scene to PNG/EXR through one view of the chip.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "asm/builtin_firmware.hpp"
#include "asm/firmware_file.hpp"
#include "cc/compiler.hpp"
#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "cli/progress.hpp"
#include "common/stats_tree.hpp"
#include "common/whole_number.hpp"
#include "config/config.hpp"
#include "device/registry.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "reference/renderer.hpp"
#include "rpu/version.hpp"
#include "scene/geometry.hpp"
#include "scene/resolve.hpp"

namespace rpu::cli {
namespace {

// The double-precision renderer: not a device (no ISA, configuration or memory image),
// so not one of the registry's backends, and `rpu render`'s default.
constexpr std::string_view kReference = "reference";

struct RenderOptions {
  std::string scene;
  std::vector<std::filesystem::path> outputs{"render.png"};
  std::string backend{kReference};
  device::Registry backends;  // the device backends, with their own options
  std::vector<std::filesystem::path> firmware;  // empty: the built-in whitted.s
  ShaderOptions shaders;                        // -D, -I, --spec-constant for GLSL firmware
  std::string select = "1";                     // docs/selection.md
  std::filesystem::path compare;                // .exr to measure the image against
  std::uint64_t watchdog = device::DeviceOptions{}.watchdog;
  std::vector<std::filesystem::path> stats;  // .json / .csv
  int scale_exponent = 0;                   // the scene times 2^this
  std::vector<double> translate{0, 0, 0};   // then moved by this
  RenderSettings settings;
  ChipOptions chip;
};

// The reference renderer: double precision, no ISA. Returns the rays by type.
Image render_reference(const Scene& scene, const RenderSettings& settings, RayCounts& counts) {
  const ReferenceRenderer renderer(scene);
  ProgressBar bar(fmt::format("rendering {}", scene.source));
  return renderer.render(settings, &counts, [&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
}

// whitted.s turns pixel coordinates into floats: a format whose largest number is below
// the image's width or height would overflow them and render nothing but background.
void check_builtin_firmware_format(fp::Format format, const RenderSettings& s) {
  const double largest = std::ldexp(2.0 - std::ldexp(1.0, -format.fraction_bits), format.max_exponent());
  if (largest < std::max(s.width, s.height)) {
    throw Error(fmt::format("number format {}: its largest number, {}, is below the image's {}x{} pixel "
                            "coordinates, which the built-in firmware computes in it; choose a format with more "
                            "exponent bits (docs/numbers.md) or a smaller image",
                            format.name(), largest, s.width, s.height));
  }
}

// A frame of one colour is what a format too narrow for the scene's arithmetic (or a
// camera that sees nothing) gives: say so rather than leave a plain image unexplained.
// `format`: the device's number format (none on the reference backend).
void warn_if_constant(const Image& image, const std::optional<std::string>& format) {
  if (image.pixels.size() < 2) return;
  const glm::vec3 first = image.pixels.front();
  std::size_t not_finite = 0;
  bool constant = true;
  for (const glm::vec3& p : image.pixels) {
    constant = constant && std::memcmp(&p, &first, sizeof p) == 0;
    not_finite += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? 0 : 1;
  }
  if (not_finite != 0) {
    fmt::print(stderr, "rpu: warning: {} of {} pixels are NaN or infinite\n", not_finite, image.pixels.size());
  }
  if (constant) {
    fmt::print(stderr,
               "rpu: warning: every pixel of the image is ({}, {}, {}){}; the camera may see nothing, or the number "
               "format's range or precision is too small for the scene's arithmetic (docs/numbers.md)\n",
               first.x, first.y, first.z, format ? fmt::format(" (format {})", *format) : "");
  }
}

// The facts of the run in its statistics (docs/cycle-model.md, "Statistics"): how it
// was started, what it rendered, what built the tool.
void record_run(StatsTree& report, const RenderOptions& o, const std::string& scene, int host_threads) {
  StatsTree& run = report.group("run");
  const RenderSettings& s = o.settings;
  run.set("command_line", invocation().command_line).set("backend", o.backend).set("scene", scene);
  run.set("width", s.width).set("height", s.height).set("spp", s.spp).set("max_depth", s.max_depth).set("seed", s.seed);
  run.set("version", std::string(kVersion)).set("commit", std::string(kCommit));
  run.set("host_seconds",
          std::chrono::duration<double>(std::chrono::steady_clock::now() - invocation().start).count());
  run.set("host_threads", host_threads);
}

// A device's facts of the run: its number format, test and selection, and the whole
// resolved configuration.
void record_chip(StatsTree& report, const RenderOptions& o) {
  report.group("run")
      .set("format", o.chip.number_format().name())
      .set("isect", o.chip.isect)
      .set("select", to_string(o.settings.select));
  const spec::HardwareConfig& c = o.chip.hardware_config();
  StatsTree& cfg = report.group("config");
  cfg.set("name", c.name).set("doc", c.doc);
  for (const config::Entry& e : config::entries(c)) {
    StatsTree* group = &cfg;
    std::string_view name = e.name;
    for (std::size_t dot = name.find('.'); dot != std::string_view::npos; dot = name.find('.')) {
      group = &group->group(name.substr(0, dot));
      name.remove_prefix(dot + 1);
    }
    std::visit([&](const auto& value) { group->set(name, value); }, e.value);
  }
}

// The --compare image: linear (.exr), the render's size, every value finite.
Image read_compare_image(const RenderOptions& o) {
  const std::string name = o.compare.string();
  if (o.compare.extension() != ".exr") {
    throw Error(fmt::format("--compare {}: give a linear .exr (a .png holds 8-bit sRGB, too coarse to measure "
                            "against)",
                            name));
  }
  Image reference = read_image(o.compare);
  if (reference.width != o.settings.width || reference.height != o.settings.height) {
    throw Error(fmt::format("--compare {}: the image is {}x{} pixels, the render {}x{}", name, reference.width,
                            reference.height, o.settings.width, o.settings.height));
  }
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const glm::vec3& p = reference.at(x, y);
      if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) {
        throw Error(fmt::format("--compare {}: pixel ({}, {}) is not finite", name, x, y));
      }
    }
  }
  return reference;
}

// The image against the --compare image: PSNR as psnr_srgb measures it, the largest
// difference of one channel of one pixel in linear values, and the dark dots.
struct Comparison {
  double psnr_db = 0.0;
  double max_error = 0.0;
  std::size_t dark_dots = 0;
};

void record_comparison(StatsTree& report, const std::filesystem::path& image, const Comparison& c) {
  report.group("compare")
      .set("image", image.string())
      .set("psnr_db", c.psnr_db)
      .set("max_error", c.max_error)
      .set("dark_dots", static_cast<std::uint64_t>(c.dark_dots));
}

Comparison compare_images(const Image& reference, const Image& image) {
  Comparison c;
  c.psnr_db = psnr_srgb(reference, image);
  c.dark_dots = dark_dots(reference, image);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double d = std::abs(static_cast<double>(image.pixels[i][k]) - reference.pixels[i][k]);
      if (std::isnan(d)) {  // a NaN in the image: the error is NaN
        c.max_error = d;
        return c;
      }
      c.max_error = std::max(c.max_error, d);
    }
  }
  return c;
}

// Firmware on a device of `backend`, which writes its own outputs after the frame; then
// the statistics, with the comparison against `reference` if there is one.
Image render_device(const Scene& world, device::Backend& backend, const RenderOptions& o,
                    const std::optional<Image>& reference, std::optional<Comparison>& comparison,
                    std::string& summary) {
  const KdBuildConfig build = o.chip.build_config();
  const Scene scene = functional::chip_space_scene(world, build.format);
  const functional::SceneImage si = functional::make_scene_image(scene, build, o.chip.isect_mode());
  // Firmware of the user's own sees the scaled scene: a length it writes is in chip units.
  if (const int s = kd_scale_exponent(world, build.format); s != 0 && !o.firmware.empty()) {
    fmt::print(stderr,
               "rpu: note: the shaders see the scene in chip space, its lengths times 2^{} = {:g} (its largest "
               "coordinate {:g} is {:g} there); a length a shader writes is in chip units (docs/shaders.md "
               "\"Coordinates\")\n",
               -s, std::ldexp(1.0, -s), largest_coordinate(world), std::ldexp(largest_coordinate(world), -s));
  }
  if (o.firmware.empty()) check_builtin_firmware_format(build.format, o.settings);
  const isa::Firmware firmware = load_firmware(o.firmware, o.shaders);
  const device::DeviceOptions options{
      .watchdog = o.watchdog, .host_threads = o.settings.threads, .isect = o.chip.isect_mode()};
  const std::unique_ptr<device::Device> dev = backend.make(o.chip.hardware_config(), build.format, options);
  Image image;
  {
    ProgressBar bar(fmt::format("rendering {} ({}, {}, {})", scene.source, o.backend, o.chip.config,
                                build.format.name()));
    image = device::render_frame(*dev, scene, si.image, firmware, o.settings,
                                 [&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
  }
  device::DeviceStats st = dev->stats();
  const functional::ShaderStats& sh = st.shader;
  std::string classes;
  for (std::size_t i = 0; i < sh.retired.size(); ++i) {
    classes += fmt::format("{}{} {}", i ? ", " : "", spec::isa::kClassNames[i], millions(sh.retired[i]));
  }
  // Rays that met the triangle they leave: docs/accuracy.md "Self-hits".
  const std::string self_hits = sh.self_hits_counted ? fmt::format(", {} self-hits", sh.self_hits) : "";
  summary = fmt::format("{} instructions ({}), SIMD efficiency {:.1f}% (chunk {}); {} rays ({} closest-hit, {} any-hit{}); "
                        "traversal {} nodes, {} leaves, {} triangle tests",
                        millions(sh.instructions()), classes,
                        100.0 * static_cast<double>(sh.instructions()) / static_cast<double>(std::max<std::uint64_t>(1, sh.lanes_issued)),
                        o.chip.hardware_config().chunk_size, millions(sh.closest_rays + sh.any_rays),
                        millions(sh.closest_rays), millions(sh.any_rays), self_hits, millions(sh.nodes),
                        millions(sh.leaves), millions(sh.tests));
  backend.finish(st);
  // The tree the frame walked: a narrow format that cannot place the planes a scene
  // needs builds few nodes and tests many triangles a ray (docs/kdtree.md).
  st.report.group("tree")
      .set("nodes", si.tree_stats.nodes)
      .set("leaves", si.tree_stats.leaves)
      .set("max_depth", si.tree_stats.max_depth)
      .set("mean_prims_per_leaf", si.tree_stats.mean_prims_per_leaf)
      .set("prim_refs", si.tree_stats.prim_refs)
      .set("sah_cost", si.tree_stats.sah_cost);
  if (reference) {
    comparison = compare_images(*reference, image);
    record_comparison(st.report, o.compare, *comparison);
  }
  if (!o.stats.empty()) {
    record_run(st.report, o, world.source, st.host_threads);
    record_chip(st.report, o);
  }
  for (const std::filesystem::path& f : o.stats) write_stats(st.report, f);
  return image;
}

// Every file the render will write (with the device `backend`'s own), and the files it
// reads that none may overwrite.
void check_render_outputs(const RenderOptions& o, const device::Backend* backend) {
  std::vector<PlannedOutput> outputs;
  for (const std::filesystem::path& f : o.outputs) outputs.push_back({"-o", f, {".png", ".exr"}});
  for (const std::filesystem::path& f : o.stats) outputs.push_back({"--stats", f, {".json", ".csv"}});
  if (backend) {
    for (const device::BackendOutput& f : backend->outputs()) outputs.push_back({f.option, f.path, f.extensions});
  }
  std::vector<PlannedInput> inputs;
  if (std::error_code ec; std::filesystem::is_regular_file(o.scene, ec)) inputs.push_back({"the scene", o.scene});
  for (const auto& f : o.firmware) inputs.push_back({"the firmware", f});
  if (!o.compare.empty()) inputs.push_back({"the --compare image", o.compare});
  check_outputs(outputs, inputs);
}

// The options that only a device backend reads: the reference renderer computes in
// double precision, without firmware, chip configuration or kd-tree.
constexpr std::string_view kDeviceOptions[] = {"--firmware",     "--select",          "--watchdog",     "--config",
                                               "--set",          "--format",          "--isect",        "--kd-depth",
                                               "--leaf-prims",   "--traversal-cost",  "--intersection-cost",
                                               "--empty-bonus",  "--perfect-splits",  "-D",
                                               "-I",             "--spec-constant"};

void check_reference_options(const CLI::App& command, const Scene& scene) {
  std::vector<std::string_view> given;
  for (const std::string_view name : kDeviceOptions) {
    if (command.count(std::string(name)) != 0) given.push_back(name);
  }
  if (!given.empty()) {
    throw Error(fmt::format("{} {} no effect on the reference backend, which renders in double precision "
                            "without firmware, chip configuration or kd-tree; use --backend functional or cycle",
                            fmt::join(given, ", "), given.size() == 1 ? "has" : "have"));
  }
  for (const Material& m : scene.materials) {
    if (m.shader != Material{}.shader) {
      fmt::print(stderr,
                 "rpu: warning: material '{}' names the shader '{}'; the reference backend shades every "
                 "material with its built-in Whitted model (docs/shading.md)\n",
                 m.name, m.shader);
    }
  }
}

// --scale-exponent and --translate: the same scene further from the format's comfortable
// range (docs/sweeps.md, "Extremes"). A vertex that overflows float is refused.
Scene transformed(Scene scene, const RenderOptions& o) {
  if (o.scale_exponent != 0) scale_scene(scene, o.scale_exponent);
  const glm::dvec3 offset(o.translate[0], o.translate[1], o.translate[2]);
  if (offset != glm::dvec3(0.0)) translate_scene(scene, offset);
  for (const glm::vec3& p : scene.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error(fmt::format("{}: --scale-exponent {} --translate {} {} {} takes a vertex beyond float's range",
                              scene.source, o.scale_exponent, offset.x, offset.y, offset.z));
    }
  }
  return scene;
}

int run_render(const RenderOptions& options, const CLI::App& command) {
  // The device backend chosen; none: the reference renderer.
  device::Backend* backend = options.backends.find(options.backend);
  options.backends.refuse_others(options.backend);
  if (backend) backend->check(options.settings, options.select);
  check_render_outputs(options, backend);
  const Scene scene = transformed(resolve_scene(options.scene), options);
  for (const std::string& warning : scene.warnings) fmt::print(stderr, "rpu: warning: {}\n", warning);
  if (!backend) check_reference_options(command, scene);

  std::optional<Image> reference;
  if (!options.compare.empty()) reference = read_compare_image(options);

  const auto start = std::chrono::steady_clock::now();
  RayCounts counts;
  std::string device_summary;
  std::optional<Comparison> comparison;
  const Image image = backend ? render_device(scene, *backend, options, reference, comparison, device_summary)
                              : render_reference(scene, options.settings, counts);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  warn_if_constant(image, backend ? std::optional(options.chip.number_format().name()) : std::nullopt);
  std::vector<std::string> written;
  for (const std::filesystem::path& out : options.outputs) {
    write_image(image, out);
    written.push_back(out.string());
  }
  if (reference) {
    if (!comparison) comparison = compare_images(*reference, image);
    fmt::print(stderr, "rpu: against {}: PSNR {:.2f} dB, max error {:.6g}, {} dark dots ({:.3f}% of the image)\n",
               options.compare.string(), comparison->psnr_db, comparison->max_error, comparison->dark_dots,
               100.0 * static_cast<double>(comparison->dark_dots) / static_cast<double>(image.pixels.size()));
  }
  if (!backend && !options.stats.empty()) {
    // The reference keeps only its rays by type and the facts of the run.
    StatsTree report;
    report.group("rays")
        .set("total", counts.total())
        .set("primary", counts.primary)
        .set("shadow", counts.shadow)
        .set("reflection", counts.reflection)
        .set("refraction", counts.refraction);
    if (comparison) record_comparison(report, options.compare, *comparison);
    record_run(report, options, scene.source, options.settings.threads);
    for (const std::filesystem::path& f : options.stats) write_stats(report, f);
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
  std::vector<std::string> backends{std::string(kReference)};
  for (const std::string& name : render->backends.names()) backends.push_back(name);
  render_cmd->add_option("--backend", render->backend, "Which view of the chip renders")
      ->check(CLI::IsMember(backends))
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

  render_cmd->add_option("--scale-exponent", render->scale_exponent,
                         "Scale the scene (geometry, camera, lights) by 2^K before rendering")
      ->check(CLI::Range(-100, 100))
      ->capture_default_str();
  render_cmd->add_option("--translate", render->translate, "Then move it by X Y Z")
      ->expected(3)
      ->check(CLI::Validator(
          [](const std::string& text) {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            return end != text.c_str() && *end == '\0' && std::isfinite(v) && std::abs(v) <= 1e30
                       ? std::string()
                       : fmt::format("{} is not a finite number within 1e30", text);
          },
          "NUMBER"));
  render_cmd->add_option("--firmware", render->firmware,
                         "device backends: firmware (.s or .rfw), or GLSL shaders (.rgen .rchit .rmiss, compiled by "
                         "`rpu cc` and cached), instead of the built-in whitted.s")
      ->expected(1, -1);
  add_shader_options(*render_cmd, render->shaders);
  render_cmd->add_option("--select", render->select,
                         "device backends: selected ray tracing, BLOCK[:THRESHOLD[:material|primitive]]: trace the "
                         "corners of BLOCK x BLOCK blocks, interpolate where they agree (docs/selection.md)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            try {
              parse_selection(text);
              return std::string();
            } catch (const Error& e) {
              return std::string(e.what());
            }
          },
          "SELECTION"))
      ->each([render](const std::string& text) { render->settings.select = parse_selection(text); })
      ->capture_default_str();
  render_cmd->add_option("--watchdog", render->watchdog,
                         "device backends: instructions one thread may retire for one pixel before it "
                         "faults")
      ->check(whole_number("the watchdog (instructions)", 1))
      ->capture_default_str();
  render_cmd->add_option("--compare", render->compare,
                         "Measure the image against this linear .exr of the same size (e.g. the reference "
                         "backend's): PSNR (sRGB, peak 1), the largest linear difference and the dark dots (isolated "
                         "pixels under 0.6 of its luminance, docs/accuracy.md \"Dark dots\"), printed and in --stats as "
                         "compare.psnr_db, compare.max_error and compare.dark_dots");
  render_cmd->add_option("--stats", render->stats,
                         "statistics and the facts of the run, .json and/or .csv (one wide row under a header of "
                         "metric names); the reference backend records its rays by type, the functional and cycle backends "
                         "also the rays that met the triangle they leave (rays.self_hits)");
  render->backends.add_options(*render_cmd);
  add_chip_options(*render_cmd, render->chip);

  return {render_cmd, [render, render_cmd] { return run_render(*render, *render_cmd); }};
}

}  // namespace rpu::cli
