#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cc/compiler.hpp"
#include "fp/format.hpp"
#include "isa/firmware.hpp"
#include "kdtree/kdtree.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

namespace rpu::cli {

// Options shared by the commands that build what the chip reads: which hardware
// configuration (named, or a TOML file, with --set changes: docs/configurations.md),
// number format, intersection test and kd-tree build parameters.
struct ChipOptions {
  std::string config = "default";
  std::vector<std::string> sets;  // "key=value", applied in order
  std::string format;  // empty: the configuration's format
  std::string isect = "woop";
  std::optional<int> max_depth;  // none: the configuration's stack depth
  KdBuildConfig build;

  // Resolves the configuration (once; --format counts as a last --set format=...);
  // throws rpu::Error for an unknown name or key, a bad value, or an impossible
  // combination (a tree deeper than the stack).
  KdBuildConfig build_config() const;
  fp::Format number_format() const;
  const spec::HardwareConfig& hardware_config() const;
  IsectMode isect_mode() const { return isect == "watertight" ? IsectMode::kWatertight : IsectMode::kWoop; }

 private:
  mutable std::optional<spec::HardwareConfig> resolved_;
};

void add_chip_options(CLI::App& command, ChipOptions& options);

// The GLSL front end's options of rpu cc, and of rpu render for GLSL --firmware: -D,
// -I and --spec-constant (docs/shaders.md).
struct ShaderOptions {
  std::vector<std::string> defines;         // NAME or NAME=VALUE
  std::vector<std::string> include_dirs;
  std::vector<std::string> spec_constants;  // ID=VALUE

  bool given() const { return !defines.empty() || !include_dirs.empty() || !spec_constants.empty(); }
  // Checked: a bad macro name, ID=VALUE or directory is an rpu::Error.
  cc::CompileOptions compile_options() const;
};

void add_shader_options(CLI::App& command, ShaderOptions& options);

// What --firmware names: none, the built-in whitted.s; one assembly source or firmware
// file; or GLSL shaders, compiled on the fly (rpu cc, cached by content), their
// warnings printed.
isa::Firmware load_firmware(const std::vector<std::filesystem::path>& files, const ShaderOptions& shaders = {});

}  // namespace rpu::cli
