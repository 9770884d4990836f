#include "cli/chip_options.hpp"

#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "asm/firmware_file.hpp"
#include "cc/compiler.hpp"
#include "common/error.hpp"
#include "config/config.hpp"
#include "rpu/spec.hpp"

namespace rpu::cli {

KdBuildConfig ChipOptions::build_config() const {
  KdBuildConfig c = kd_build_config_for(hardware_config());
  c.traversal_cost = build.traversal_cost;
  c.intersection_cost = build.intersection_cost;
  c.empty_bonus = build.empty_bonus;
  c.max_leaf_prims = build.max_leaf_prims;
  c.perfect_splits = build.perfect_splits;
  // Any given depth, a negative one too, goes to the builder's range check.
  if (max_depth) c.max_depth = *max_depth;
  return c;
}

const spec::HardwareConfig& ChipOptions::hardware_config() const {
  if (!resolved_) {
    std::vector<config::Change> all = config::set_options(sets);
    if (!format.empty()) all.push_back({"format=" + format, "--format " + format});
    resolved_ = config::resolve_changed(config, all);
  }
  return *resolved_;
}

fp::Format ChipOptions::number_format() const { return fp::format_by_name(hardware_config().format); }

void add_chip_options(CLI::App& command, ChipOptions& o) {
  std::string names;
  for (const spec::HardwareConfig& c : spec::kConfigs) names += (names.empty() ? "" : ", ") + c.name;
  command.add_option("--config", o.config, "Hardware configuration: " + names + ", or a TOML file (docs/configurations.md)")
      ->capture_default_str();
  command.add_option("--set", o.sets, "Change one configuration key, e.g. --set shader_cores=8 (repeatable)")
      ->type_name("KEY=VALUE");
  command.add_option("--format", o.format,
                     "Number format: fp32, e8m15, rpu24, bf16, fp16 or E<e>M<m> (default: the configuration's)");
  command.add_option("--isect", o.isect, "Ray/triangle test")
      ->check(CLI::IsMember({"woop", "watertight"}))
      ->capture_default_str();
  command.add_option("--kd-depth", o.max_depth, "kd-tree depth limit (default: the configuration's stack depth)");
  command.add_option("--leaf-prims", o.build.max_leaf_prims, "Make a leaf at this many triangles or fewer")
      ->capture_default_str();
  command.add_option("--traversal-cost", o.build.traversal_cost, "SAH traversal cost K_T")->capture_default_str();
  command.add_option("--intersection-cost", o.build.intersection_cost, "SAH intersection cost K_I")
      ->capture_default_str();
  command.add_option("--empty-bonus", o.build.empty_bonus, "SAH empty-space bonus lambda")->capture_default_str();
  command.add_flag("--perfect-splits", o.build.perfect_splits, "Clip triangles to node boxes for split candidates");
}

cc::CompileOptions ShaderOptions::compile_options() const {
  cc::CompileOptions o;
  for (const std::string& d : defines) cc::check_define(d);
  o.defines = defines;
  for (const std::string& dir : include_dirs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) throw Error(fmt::format("-I {}: not a directory", dir));
    o.include_dirs.emplace_back(dir);
  }
  for (const std::string& s : spec_constants) {
    const auto [id, value] = cc::parse_spec_constant(s);
    if (!o.spec_constants.emplace(id, value).second) {
      throw Error(fmt::format("--spec-constant {}: constant_id {} is given twice", s, id));
    }
  }
  return o;
}

void add_shader_options(CLI::App& command, ShaderOptions& o) {
  command.add_option("-D", o.defines, "GLSL: #define NAME VALUE (1 if no value) before every shader (repeatable)")
      ->type_name("NAME[=VALUE]");
  command.add_option("-I", o.include_dirs,
                     "GLSL: a directory #include \"x\" searches after the including file's own (repeatable)")
      ->type_name("DIR");
  command.add_option("--spec-constant", o.spec_constants,
                     "GLSL: the value of the specialization constant layout(constant_id = ID) (repeatable)")
      ->type_name("ID=VALUE");
}

isa::Firmware load_firmware(const std::vector<std::filesystem::path>& files, const ShaderOptions& shaders) {
  if (files.empty() && !shaders.given()) return isa::builtin_firmware("whitted.s");
  const std::string ext = files.empty() ? std::string() : files[0].extension().string();
  if (files.size() <= 1 && ext != ".rgen") {
    if (shaders.given()) {
      throw Error("-D, -I and --spec-constant are for GLSL shaders, and --firmware names none");
    }
    return isa::load_firmware_or_assemble(files[0]);
  }
  for (const auto& f : files) {
    if (f.extension() == ".s" || f.extension() == ".rfw") {
      throw Error(fmt::format("--firmware {}: give one assembly source or firmware file, or GLSL shaders "
                              "(.rgen, .rchit, .rmiss) only",
                              f.string()));
    }
  }
  cc::Compiled compiled = cc::compile_cached(files, shaders.compile_options());
  for (const std::string& w : compiled.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
  return std::move(compiled.firmware);
}

}  // namespace rpu::cli
