// libFuzzer target: rpu::config::parse on arbitrary text, the reader of `--config
// FILE.toml`. It either returns a configuration that meets every rule of
// spec/config_keys.toml or throws rpu::Error; a returned one must print (to_toml) and
// read back to the same values.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "common/error.hpp"
#include "config/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rpu::spec::HardwareConfig config;
  try {
    config = rpu::config::parse(text, "fuzz.toml");
  } catch (const rpu::Error&) {
    return 0;
  }
  for (const rpu::spec::ConfigRule& rule : rpu::spec::kConfigRules) {
    if (!rule.holds(config)) std::abort();
  }
  const rpu::spec::HardwareConfig again = rpu::config::parse(rpu::config::to_toml(config), "again.toml");
  if (rpu::config::entries(again) != rpu::config::entries(config)) std::abort();
  return 0;
}
