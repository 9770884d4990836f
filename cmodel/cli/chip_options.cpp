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

isa::Firmware load_firmware(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) return isa::builtin_firmware("whitted.s");
  const std::string ext = files[0].extension().string();
  if (files.size() == 1 && ext != ".rgen") return isa::load_firmware_or_assemble(files[0]);
  for (const auto& f : files) {
    if (f.extension() == ".s" || f.extension() == ".rfw") {
      throw Error(fmt::format("--firmware {}: give one assembly source or firmware file, or GLSL shaders "
                              "(.rgen, .rchit, .rmiss) only",
                              f.string()));
    }
  }
  return cc::compile_cached(files, {});
}

}  // namespace rpu::cli
