#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "fp/format.hpp"
#include "kdtree/kdtree.hpp"
#include "memory/memory_image.hpp"
#include "rpu/spec.hpp"

namespace rpu::cli {

// Options shared by the commands that build what the chip reads: which hardware
// configuration (spec/configs.toml), number format, intersection test and kd-tree
// build parameters.
struct ChipOptions {
  std::string config = "default";
  std::string format;  // empty: the configuration's format
  std::string isect = "woop";
  std::optional<int> max_depth;  // none: the configuration's stack depth
  KdBuildConfig build;

  // Resolves the configuration; throws rpu::Error for unknown names or an impossible
  // combination (a tree deeper than the stack).
  KdBuildConfig build_config() const;
  fp::Format number_format() const;
  const spec::HardwareConfig& hardware_config() const;
  IsectMode isect_mode() const { return isect == "watertight" ? IsectMode::kWatertight : IsectMode::kWoop; }
};

void add_chip_options(CLI::App& command, ChipOptions& options);

}  // namespace rpu::cli
