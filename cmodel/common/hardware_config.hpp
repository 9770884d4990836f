#pragma once

#include <string>
#include <string_view>

#include "common/error.hpp"
#include "rpu/spec.hpp"

namespace rpu {

// The named hardware configuration of spec/configs.toml; rpu::Error lists the names
// for an unknown one.
inline const spec::HardwareConfig& hardware_config(std::string_view name) {
  std::string names;
  for (const spec::HardwareConfig& c : spec::kConfigs) {
    if (c.name == name) return c;
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  }
  throw Error("unknown hardware configuration '" + std::string(name) + "' (spec/configs.toml has " + names + ")");
}

}  // namespace rpu
