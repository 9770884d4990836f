// rpu fit: the smallest configuration that renders one scene within a target, found by
// narrowing one parameter at a time on the cycle model, and proved: it meets the target
// and each parameter one step narrower fails it (docs/fit.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "common/error.hpp"
#include "common/output_file.hpp"
#include "config/config.hpp"
#include "device/registry.hpp"
#include "functional/scene_image.hpp"
#include "image/image.hpp"
#include "kdtree/kdtree.hpp"
#include "reference/renderer.hpp"
#include "rpu/spec.hpp"
#include "scene/resolve.hpp"
#include "sweep/area.hpp"
#include "sweep/ray_checks.hpp"

namespace rpu::cli {
namespace {

namespace fs = std::filesystem;

struct FitOptions {
  std::string scene;
  double min_psnr = 40.0;
  std::optional<std::uint64_t> max_leaks;
  double max_slowdown = 0.10;
  double hit_rate_drop = 0.02;
  std::string base = "default";
  std::string isect = "woop";
  std::vector<fs::path> firmware;
  std::vector<std::string> formats;  // the candidates; empty: every format of spec/formats.toml
  std::uint32_t leak_rays = 4096;
  RenderSettings settings;
  fs::path output;
  fs::path json;  // the fit as one JSON document (scripts/bench-record fit reads it)
};

constexpr const char* kCaches[] = {"node_cache", "triangle_cache", "data_cache"};

// What one configuration did with the scene.
struct Outcome {
  std::string error;  // non-empty: it could not render the scene
  double psnr = 0.0;
  double cycles = 0.0;
  double sah_cost = 0.0;                   // of the kd-tree its format built
  std::map<std::string, double> hit_rate;  // by cache
  std::uint64_t leaks = 0, leak_rays = 0;
};

using Sets = std::map<std::string, std::string>;  // key -> value, over the base

std::vector<std::string> as_sets(const Sets& sets) {
  std::vector<std::string> out;
  for (const auto& [k, v] : sets) out.push_back(k + "=" + v);
  return out;
}

std::string psnr_text(double psnr) { return std::isinf(psnr) ? "identical" : fmt::format("{:.1f} dB", psnr); }

class Fitter {
 public:
  Fitter(const FitOptions& o, Scene world)
      : o_(o), world_(std::move(world)), firmware_(load_firmware(o.firmware)) {
    reference_ = ReferenceRenderer(world_).render(o_.settings, nullptr, {});
    base_ = evaluate({});
    if (!base_.error.empty()) throw Error(fmt::format("the base configuration '{}' cannot render the scene: {}", o_.base, base_.error));
  }

  const Outcome& base() const { return base_; }

  spec::HardwareConfig resolve(const Sets& sets) const { return config::resolve(o_.base, as_sets(sets)); }

  // The clauses of the target that `out` breaks; none: it meets the target.
  std::vector<std::string> failures(const Outcome& out) const {
    if (!out.error.empty()) return {out.error};
    std::vector<std::string> why;
    if (out.psnr < o_.min_psnr) why.push_back(fmt::format("PSNR {} < {} dB", psnr_text(out.psnr), o_.min_psnr));
    if (o_.max_leaks && out.leaks > *o_.max_leaks) {
      why.push_back(fmt::format("{} of {} rays leak > {}", out.leaks, out.leak_rays, *o_.max_leaks));
    }
    const double budget = (1.0 + o_.max_slowdown) * base_.cycles;
    if (out.cycles > budget) {
      // A format that cannot place the scene's planes spends its cycles in the triangle
      // tests of coarse leaves (docs/kdtree.md "Conservative splits in any format").
      const bool lost_planes = out.sah_cost > kLostPlanesRatio * base_.sah_cost;
      why.push_back(fmt::format("{:.0f} cycles > {:.0f}{}", out.cycles, budget,
                                lost_planes ? fmt::format(" (its kd-tree's SAH cost is {:.1f} times the base's: the "
                                                          "format cannot place the planes the scene needs)",
                                                          out.sah_cost / base_.sah_cost)
                                            : ""));
    }
    for (const auto& [cache, rate] : out.hit_rate) {
      const double floor = base_.hit_rate.at(cache) - o_.hit_rate_drop;
      if (rate < floor) why.push_back(fmt::format("{} hit rate {:.4f} < {:.4f}", cache, rate, floor));
    }
    return why;
  }

  const Outcome& evaluate(const Sets& sets) {
    const std::string key = fmt::format("{}", fmt::join(as_sets(sets), " "));
    if (auto found = cache_.find(key); found != cache_.end()) return found->second;
    Outcome out;
    try {
      ChipOptions chip;
      chip.config = o_.base;
      chip.sets = as_sets(sets);
      chip.isect = o_.isect;
      const KdBuildConfig build = chip.build_config();
      const Scene scene = functional::chip_space_scene(world_, build.format);
      const functional::SceneImage si = functional::make_scene_image(scene, build, chip.isect_mode());
      const std::unique_ptr<device::Device> dev = device::make_device("cycle", chip.hardware_config(), build.format);
      const Image image = device::render_frame(*dev, scene, si.image, firmware_, o_.settings);
      const device::DeviceStats st = dev->stats();
      out.psnr = psnr_srgb(reference_, image);
      out.sah_cost = si.tree_stats.sah_cost;
      out.cycles = st.report.number("cycles");
      for (const char* cache : kCaches) {
        const std::string name = std::string(cache).substr(0, std::string(cache).find('_'));
        out.hit_rate[cache] = st.report.number(fmt::format("caches.{}.hit_rate", name));
      }
      if (o_.max_leaks) {
        const sweep::RayChecks c = sweep::check_rays(world_, build, chip.isect_mode(), o_.settings.width,
                                                     o_.settings.height, false, o_.leak_rays, o_.settings.seed);
        out.leaks = c.leaks;
        out.leak_rays = c.leak_rays;
      }
    } catch (const Error& e) {
      out.error = fmt::format("does not run: {}", e.what());
    }
    ++evaluations_;
    return cache_.emplace(key, std::move(out)).first->second;
  }

  int evaluations() const { return evaluations_; }
  const isa::Firmware& firmware() const { return firmware_; }

 private:
  const FitOptions& o_;
  Scene world_;
  isa::Firmware firmware_;
  Image reference_;
  Outcome base_;
  std::map<std::string, Outcome> cache_;
  int evaluations_ = 0;
};

// One parameter the fit narrows, and its next narrower value.
struct Parameter {
  std::string key;
  std::function<std::optional<std::string>(const spec::HardwareConfig&)> narrower;
  std::string value(const spec::HardwareConfig& c) const {
    for (const config::Entry& e : config::entries(c)) {
      if (e.name == key) return std::visit([](const auto& v) { return fmt::format("{}", v); }, e.value);
    }
    throw Error(fmt::format("no configuration key {}", key));
  }
};

// The candidate formats from the widest to the narrowest (by total bits, then fraction
// bits): a step narrower is the next one.
std::vector<std::string> formats_by_width(const std::vector<std::string>& names) {
  std::vector<std::pair<fp::Format, std::string>> f;
  if (names.empty()) {
    for (const spec::FormatSpec& s : spec::kFormats) f.emplace_back(fp::format_by_name(s.name), s.name);
  }
  for (const std::string& n : names) f.emplace_back(fp::format_by_name(n), n);
  std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) {
    return std::pair(a.first.width(), a.first.fraction_bits) > std::pair(b.first.width(), b.first.fraction_bits);
  });
  std::vector<std::string> out;
  for (const auto& [format, name] : f) out.push_back(name);
  return out;
}

std::vector<Parameter> parameters(const std::vector<std::string>& formats) {
  std::vector<Parameter> out;
  out.push_back({"format", [order = formats_by_width(formats)](const spec::HardwareConfig& c) -> std::optional<std::string> {
                   const fp::Format mine = fp::format_by_name(c.format);
                   for (std::size_t i = 0; i + 1 < order.size(); ++i) {
                     if (fp::format_by_name(order[i]) == mine) return order[i + 1];
                   }
                   return std::nullopt;
                 }});
  const auto minus_one = [](auto member, int min) {
    return [member, min](const spec::HardwareConfig& c) -> std::optional<std::string> {
      const auto v = static_cast<std::int64_t>(c.*member);
      return v > min ? std::optional<std::string>(std::to_string(v - 1)) : std::nullopt;
    };
  };
  out.push_back({"stack_depth", minus_one(&spec::HardwareConfig::stack_depth, 1)});
  out.push_back({"registers", minus_one(&spec::HardwareConfig::registers, 1)});
  out.push_back({"call_depth", minus_one(&spec::HardwareConfig::call_depth, 1)});
  out.push_back({"stack_bytes", [](const spec::HardwareConfig& c) -> std::optional<std::string> {
                   return c.stack_bytes > 16 ? std::optional<std::string>(std::to_string(c.stack_bytes - 16))
                                             : std::nullopt;
                 }});
  for (const char* cache : kCaches) {
    out.push_back({fmt::format("{}.bytes", cache), [cache](const spec::HardwareConfig& c) -> std::optional<std::string> {
                     const spec::CacheConfig& k = std::string_view(cache) == "node_cache"       ? c.node_cache
                                                  : std::string_view(cache) == "triangle_cache" ? c.triangle_cache
                                                                                                : c.data_cache;
                     const std::int64_t half = k.bytes / 2;
                     return half >= k.line_bytes * k.ways ? std::optional<std::string>(std::to_string(half))
                                                          : std::nullopt;
                   }});
  }
  out.push_back({"shader_cores", minus_one(&spec::HardwareConfig::shader_cores, 1)});
  out.push_back({"threads_per_core", [](const spec::HardwareConfig& c) -> std::optional<std::string> {
                   const std::int64_t half = c.threads_per_core / 2;
                   return half >= c.chunk_size && half % c.chunk_size == 0
                              ? std::optional<std::string>(std::to_string(half))
                              : std::nullopt;
                 }});
  // One ray unit fewer of each cache pair's, so that the pairs still divide the units.
  out.push_back({"traversal_units", [](const spec::HardwareConfig& c) -> std::optional<std::string> {
                   const int fewer = c.traversal_units - c.ray_caches;
                   return fewer >= 1 ? std::optional<std::string>(std::to_string(fewer)) : std::nullopt;
                 }});
  out.push_back({"intersection_units", minus_one(&spec::HardwareConfig::intersection_units, 1)});
  return out;
}

std::string area_text(const sweep::AreaEstimate& a) {
  return fmt::format("{} logic cells, {:.1f} KiB of RAM",
                     a.logic_cells ? fmt::format("{}", *a.logic_cells) : std::string("(format not synthesised)"),
                     static_cast<double>(a.ram_bits) / 8192.0);
}

std::string saving(double base, double fitted) { return fmt::format("{:+.1f}%", 100.0 * (fitted - base) / base); }

int run_fit(const FitOptions& o) {
  std::vector<PlannedOutput> outputs;
  if (!o.output.empty()) outputs.push_back({"-o", o.output, {".toml"}});
  if (!o.json.empty()) outputs.push_back({"--json", o.json, {".json"}});
  std::vector<PlannedInput> inputs;
  if (std::error_code ec; fs::is_regular_file(o.scene, ec)) inputs.push_back({"the scene", o.scene});
  check_outputs(outputs, inputs);
  Scene world = resolve_scene(o.scene);
  for (const std::string& w : world.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
  const std::size_t triangles = world.triangles.size();
  Fitter fit(o, std::move(world));
  const spec::HardwareConfig base = fit.resolve({});
  fmt::print("rpu fit {} ({} triangles), {}x{}, {} spp, max depth {}, {} test, from '{}':\n", o.scene, triangles,
             o.settings.width, o.settings.height, o.settings.spp, o.settings.max_depth, o.isect, o.base);
  fmt::print("  target: PSNR >= {} dB against the reference{}; cycles <= {:.0f} ({:.0f}% over '{}''s {:.0f}); "
             "each cache's hit rate within {} of '{}''s\n",
             o.min_psnr,
             o.max_leaks ? fmt::format(", at most {} of {} rays leaking from closed meshes", *o.max_leaks, o.leak_rays)
                         : "",
             (1.0 + o.max_slowdown) * fit.base().cycles, 100.0 * o.max_slowdown, o.base, fit.base().cycles,
             o.hit_rate_drop, o.base);
  if (const auto f = fit.failures(fit.base()); !f.empty()) {
    throw Error(fmt::format("'{}' itself misses the target ({}): lower --min-psnr or raise --max-leaks", o.base,
                            fmt::join(f, "; ")));
  }

  // Start where the scene and the firmware say: the tree's depth, the firmware's declared
  // return-stack entries and stack bytes; then narrow each parameter while the target holds,
  // until a whole pass changes nothing.
  Sets fitted;
  const auto symbol = [&](std::string_view name) -> std::optional<std::uint64_t> {
    const auto s = fit.firmware().symbols.find(name);
    if (s == fit.firmware().symbols.end() || s->second.kind != isa::Symbol::Kind::kConstant) return std::nullopt;
    return s->second.value;
  };
  const auto try_start = [&](const std::string& key, std::uint64_t value) {
    Sets trial = fitted;
    trial[key] = std::to_string(value);
    if (fit.failures(fit.evaluate(trial)).empty()) fitted = trial;
  };
  {
    ChipOptions chip;
    chip.config = o.base;
    const KdTree tree = build_kdtree(functional::chip_space_scene(resolve_scene(o.scene), chip.build_config().format),
                                     chip.build_config());
    try_start("stack_depth", static_cast<std::uint64_t>(std::max(1, tree.stats.max_depth)));
  }
  if (const auto entries = symbol("FIRMWARE_RETURN_STACK_ENTRIES")) try_start("call_depth", *entries);
  if (const auto fixed = symbol("FIRMWARE_STACK_BYTES")) {
    const std::uint64_t bytes = *fixed + symbol("FIRMWARE_STACK_BYTES_PER_DEPTH").value_or(0) * o.settings.max_depth;
    try_start("stack_bytes", std::max<std::uint64_t>(16, (bytes + 15) / 16 * 16));
  }
  const std::vector<Parameter> params = parameters(o.formats);
  for (int pass = 0; pass < 8; ++pass) {
    bool changed = false;
    for (const Parameter& p : params) {
      for (;;) {
        const std::optional<std::string> next = p.narrower(fit.resolve(fitted));
        if (!next) break;
        Sets trial = fitted;
        trial[p.key] = *next;
        std::optional<spec::HardwareConfig> valid;
        try {
          valid = fit.resolve(trial);
        } catch (const Error&) {
          break;  // the narrower value breaks a configuration rule
        }
        if (!fit.failures(fit.evaluate(trial)).empty()) break;
        fitted = trial;
        changed = true;
      }
    }
    if (!changed) break;
  }

  // The proof: the fitted configuration meets the target; each parameter one step
  // narrower does not.
  const spec::HardwareConfig chosen = fit.resolve(fitted);
  const Outcome& result = fit.evaluate(fitted);
  if (const auto f = fit.failures(result); !f.empty()) {
    throw Error(fmt::format("internal: the fitted configuration misses the target ({})", fmt::join(f, "; ")));
  }
  fmt::print("  {:<20} {:>10} {:>10} {:>12}  {}\n", "parameter", o.base, "fitted", "one narrower", "fails the target:");
  const auto optional = [](const auto& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
  nlohmann::json rows = nlohmann::json::array();
  bool proved = true;
  for (const Parameter& p : params) {
    const std::optional<std::string> next = p.narrower(chosen);
    std::string why;
    if (!next) {
      why = "(at the end of its range)";
    } else {
      Sets trial = fitted;
      trial[p.key] = *next;
      try {
        fit.resolve(trial);
        const std::vector<std::string> f = fit.failures(fit.evaluate(trial));
        why = f.empty() ? "MEETS THE TARGET" : fmt::format("{}", fmt::join(f, "; "));
        proved = proved && !f.empty();
      } catch (const Error& e) {
        why = fmt::format("not a configuration: {}", e.what());
      }
    }
    fmt::print("  {:<20} {:>10} {:>10} {:>12}  {}\n", p.key, p.value(base), p.value(chosen), next.value_or("-"), why);
    rows.push_back({{"parameter", p.key}, {"base", p.value(base)}, {"fitted", p.value(chosen)},
                    {"narrower", optional(next)}, {"narrower_fails", why}});
  }
  const IsectMode mode = o.isect == "watertight" ? IsectMode::kWatertight : IsectMode::kWoop;
  const sweep::AreaEstimate base_area = sweep::estimate_area(base, mode), fitted_area = sweep::estimate_area(chosen, mode);
  fmt::print("  fitted: PSNR {}{}, {:.0f} cycles ({} against '{}'), {}",
             psnr_text(result.psnr),
             o.max_leaks ? fmt::format(", {} of {} rays leak", result.leaks, result.leak_rays) : "", result.cycles,
             saving(fit.base().cycles, result.cycles), o.base, area_text(fitted_area));
  fmt::print(" ({}{} RAM against '{}''s {})",
             base_area.logic_cells && fitted_area.logic_cells
                 ? fmt::format("{} logic, ", saving(static_cast<double>(*base_area.logic_cells),
                                                    static_cast<double>(*fitted_area.logic_cells)))
                 : "",
             saving(static_cast<double>(base_area.ram_bits), static_cast<double>(fitted_area.ram_bits)), o.base,
             area_text(base_area));
  fmt::print("; {} renders\n", fit.evaluations());
  if (!o.json.empty()) {
    const nlohmann::json doc = {
        {"scene", o.scene}, {"triangles", triangles}, {"width", o.settings.width}, {"height", o.settings.height},
        {"spp", o.settings.spp}, {"max_depth", o.settings.max_depth}, {"isect", o.isect}, {"base", o.base},
        {"formats", o.formats},
        {"target", {{"min_psnr", o.min_psnr}, {"max_leaks", optional(o.max_leaks)}, {"leak_rays", o.leak_rays},
                    {"max_slowdown", o.max_slowdown}, {"hit_rate_drop", o.hit_rate_drop}}},
        {"base_result", {{"cycles", fit.base().cycles}, {"logic_cells", optional(base_area.logic_cells)},
                         {"ram_bits", base_area.ram_bits}}},
        {"fitted_result", {{"psnr", std::isinf(result.psnr) ? nlohmann::json() : nlohmann::json(result.psnr)},
                           {"leaks", result.leaks}, {"cycles", result.cycles},
                           {"logic_cells", optional(fitted_area.logic_cells)}, {"ram_bits", fitted_area.ram_bits}}},
        {"parameters", rows}, {"renders", fit.evaluations()}, {"proved", proved}};
    OutputFile out(o.json);
    out.stream() << doc.dump(1) << '\n';
    out.commit();
  }
  spec::HardwareConfig named = chosen;
  named.name = o.output.empty() ? "fitted" : o.output.stem().string();
  named.doc = fmt::format("fitted to {} by: {}", o.scene, invocation().command_line);
  if (!o.output.empty()) {
    OutputFile out(o.output);
    out.stream() << config::to_toml(named);
    out.commit();
    fmt::print("  -> {}\n", o.output.string());
  } else {
    fmt::print("\n{}", config::to_toml(named));
  }
  if (!proved) throw Error("a parameter one step narrower still meets the target after 8 passes; the fit is not minimal");
  return 0;
}

}  // namespace

Command add_fit_command(CLI::App& app) {
  auto o = std::make_shared<FitOptions>();
  o->settings.width = 64;
  o->settings.height = 48;
  o->settings.spp = 1;
  o->settings.threads = 0;
  CLI::App* cmd = app.add_subcommand("fit", "The smallest configuration that renders a scene within a target, with "
                                            "the proof that each parameter one step narrower fails it");
  cmd->add_option("scene", o->scene, "Scene file, built-in name or mesh file")->required();
  cmd->add_option("--min-psnr", o->min_psnr, "PSNR against the reference renderer the fitted chip must reach (dB)")
      ->required()
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--max-leaks", o->max_leaks, "Rays leaking out of the scene's closed meshes allowed (of --leak-rays)");
  cmd->add_option("--leak-rays", o->leak_rays, "Rays from inside the closed meshes")->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  cmd->add_option("--max-slowdown", o->max_slowdown, "Cycles allowed over the base configuration's, as a fraction")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--hit-rate-drop", o->hit_rate_drop, "Drop of each cache's hit rate allowed below the base's")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--base", o->base, "The configuration to start from (named or .toml)")->capture_default_str();
  cmd->add_option("--isect", o->isect, "Intersection test")->check(CLI::IsMember({"woop", "watertight"}))
      ->capture_default_str();
  cmd->add_option("--firmware", o->firmware, "Firmware (.s, .rfw) or GLSL shaders; default the built-in whitted.s")
      ->expected(1, -1);
  cmd->add_option("--formats", o->formats,
                  "The formats to choose from (default: every one of spec/formats.toml); e.g. the synthesised "
                  "fp32 rpu24 fp16, for an area estimate")
      ->expected(1, -1)
      ->check(CLI::Validator(
          [](const std::string& name) {
            try {
              fp::format_by_name(name);
              return std::string();
            } catch (const Error& e) {
              return std::string(e.what());
            }
          },
          "FORMAT"));
  cmd->add_option("--width", o->settings.width, "Image width")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--height", o->settings.height, "Image height")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--spp", o->settings.spp, "Samples per pixel")->check(CLI::Range(1, 1024))->capture_default_str();
  cmd->add_option("--max-depth", o->settings.max_depth, "Bounces")->check(CLI::Range(0, 64))->capture_default_str();
  cmd->add_option("--json", o->json, "Write the fit (target, each parameter's proof, the fitted result) as JSON");
  cmd->add_option("-o,--output", o->output, "Write the fitted configuration here (.toml; rpu --config reads it)");
  return {cmd, [o] { return run_fit(*o); }};
}

}  // namespace rpu::cli
