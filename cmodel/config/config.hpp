#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rpu/spec.hpp"

// Hardware configurations at run time (docs/configurations.md): a named one of
// spec/configs.toml or a TOML file a user writes, changed by `--set key=value`, checked
// against the keys, ranges and rules of spec/config_keys.toml and completed with the
// derived values and the measured latencies of spec/latencies.toml.
namespace rpu::config {

// `name_or_file`: a named configuration, or a .toml file holding every key of
// spec/config_keys.toml, or `base = "NAME"` and the keys it changes. Then each of `sets`
// ("key=value", dotted keys) in order. Throws rpu::Error naming the file and line, or
// the --set, for a malformed file, an unknown key (with the nearest known one), a value
// out of range or not a power of two where one is needed, and a broken rule.
spec::HardwareConfig resolve(std::string_view name_or_file, const std::vector<std::string>& sets = {});

// One key changed ("key=value") and the option that changed it, as messages name it
// ("--set key=value", "--format E5M10").
struct Change {
  std::string assignment;
  std::string option;
};
// The same with each change's own option; `sets` above are each "--set key=value".
spec::HardwareConfig resolve_changed(std::string_view name_or_file, const std::vector<Change>& changes);
std::vector<Change> set_options(const std::vector<std::string>& sets);

// The same for the text of a configuration file; `source` names it in messages.
spec::HardwareConfig parse(std::string_view toml_text, const std::string& source,
                           const std::vector<std::string>& sets = {});

// Every value of a resolved configuration by dotted name, in the order of
// spec/config_keys.toml: the choices, the derived values, the latencies and the
// latencies.toml entries they came from.
struct Entry {
  std::string name;
  std::variant<std::int64_t, std::string> value;
  enum class Kind { kChoice, kDerived, kMeasured } kind;
  friend bool operator==(const Entry&, const Entry&) = default;
};
std::vector<Entry> entries(const spec::HardwareConfig& config);

// The configuration as TOML that `resolve` reads back to the same configuration: the
// choices as keys, the derived values and latencies as comments.
std::string to_toml(const spec::HardwareConfig& config);

}  // namespace rpu::config
