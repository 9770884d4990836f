#include "config/config.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/did_you_mean.hpp"
#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "common/input_file.hpp"
#include "fp/format.hpp"

namespace rpu::config {
namespace {

// A configuration is a few dozen keys; a larger file is not one (and is not read whole).
constexpr std::uintmax_t kMaxConfigFileBytes = std::uintmax_t{1} << 20;

const spec::ConfigKey* find_key(std::string_view name) {
  for (const spec::ConfigKey& k : spec::kConfigKeys) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

std::vector<std::string_view> key_names() {
  std::vector<std::string_view> names;
  for (const spec::ConfigKey& k : spec::kConfigKeys) names.push_back(k.name);
  return names;
}

std::vector<std::string_view> config_names() {
  std::vector<std::string_view> names;
  for (const spec::HardwareConfig& c : spec::kConfigs) names.push_back(c.name);
  return names;
}

// Why a dotted name that is not a choice cannot be set, or "" for an unknown one.
std::string not_a_choice(std::string_view name) {
  for (const spec::DerivedValue& d : spec::kDerivedValues) {
    if (d.name == name) return fmt::format("'{}' is derived ({} = {}), not a choice", name, name, d.expr);
  }
  const std::string_view group = name.substr(0, name.find('.'));
  for (const spec::MeasuredValue& m : spec::kMeasuredValues) {
    if (m.name == name || m.name.substr(0, m.name.find('.')) == group) {
      return fmt::format("'{}' is measured on the RTL (spec/latencies.toml, by the format), not a choice", name);
    }
  }
  if (name == "name" || name == "doc" || name == "base") return fmt::format("'{}' belongs at the top of a file", name);
  return {};
}

std::string unknown_key(std::string_view name) {
  const std::string why = not_a_choice(name);
  if (!why.empty()) return why;
  return fmt::format("unknown key '{}'{}", quote_input(name), did_you_mean(name, key_names()));
}

// The configuration being built, and where each value came from (for messages).
struct Builder {
  spec::HardwareConfig config{};
  std::map<std::string, std::string, std::less<>> origin;

  void set_from(const spec::HardwareConfig& base, const std::string& where) {
    config = base;
    for (const spec::ConfigKey& k : spec::kConfigKeys) origin[std::string(k.name)] = where;
  }

  // Sets one choice; `where` prefixes every message ("my.toml:3:5", "--set x=1").
  void set(const spec::ConfigKey& key, const std::variant<std::int64_t, std::string>& value, const std::string& where) {
    if (key.kind == spec::KeyKind::kFormat) {
      const std::string* text = std::get_if<std::string>(&value);
      if (text == nullptr) throw Error(fmt::format("{}: {} must be a string (a format name)", where, key.name));
      try {
        (void)fp::format_by_name(*text);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", where, e.what()));
      }
      config.format = *text;
    } else {
      const std::int64_t* number = std::get_if<std::int64_t>(&value);
      if (number == nullptr) throw Error(fmt::format("{}: {} must be an integer", where, key.name));
      if (*number < key.min || *number > key.max) {
        throw Error(fmt::format("{}: {} = {} is outside [{}, {}] ({})", where, key.name, *number, key.min, key.max,
                                key.doc));
      }
      if (key.pow2 && (*number & (*number - 1)) != 0) {
        throw Error(fmt::format("{}: {} = {} is not a power of two ({})", where, key.name, *number, key.doc));
      }
      key.set(config, *number);
    }
    origin[std::string(key.name)] = where;
  }
};

std::string where_in(const std::string& file, const toml::source_region& source) {
  return fmt::format("{}:{}:{}", file, source.begin.line, source.begin.column);
}

// Walks a parsed file's keys below `prefix` into `b`, collecting the keys it set.
void read_table(const toml::table& table, const std::string& prefix, const std::string& file, Builder& b,
                std::vector<std::string>& seen) {
  for (const auto& [k, node] : table) {
    const std::string name = prefix + std::string(k.str());
    const std::string where = where_in(file, node.source());
    if (prefix.empty() && (name == "base" || name == "name" || name == "doc")) continue;
    if (const toml::table* sub = node.as_table()) {
      read_table(*sub, name + ".", file, b, seen);
      continue;
    }
    const spec::ConfigKey* key = find_key(name);
    if (key == nullptr) throw Error(fmt::format("{}: {}", where, unknown_key(name)));
    if (const auto* i = node.as_integer()) {
      b.set(*key, i->get(), where);
    } else if (const auto* s = node.as_string()) {
      b.set(*key, s->get(), where);
    } else {
      throw Error(fmt::format("{}: {} must be {}", where, name,
                              key->kind == spec::KeyKind::kFormat ? "a string (a format name)" : "an integer"));
    }
    seen.push_back(name);
  }
}

std::optional<std::string> top_string(const toml::table& table, std::string_view key, const std::string& file) {
  const toml::node* node = table.get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_string()) throw Error(fmt::format("{}: {} must be a string", where_in(file, node->source()), key));
  return node->as_string()->get();
}

void read_text(std::string_view text, const std::string& file, Builder& b) {
  toml::table table;
  try {
    table = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw Error(fmt::format("{}: {}", where_in(file, e.source()), e.description()));
  }
  const std::optional<std::string> base = top_string(table, "base", file);
  if (base) {
    const auto named = std::find_if(spec::kConfigs.begin(), spec::kConfigs.end(),
                                    [&](const spec::HardwareConfig& c) { return c.name == *base; });
    if (named == spec::kConfigs.end()) {
      throw Error(fmt::format("{}: base = \"{}\" is not a named configuration (spec/configs.toml has {}){}",
                              where_in(file, table.get("base")->source()), *base, fmt::join(config_names(), ", "),
                              did_you_mean(*base, config_names())));
    }
    b.set_from(*named, fmt::format("config '{}'", *base));
  }
  std::vector<std::string> seen;
  read_table(table, "", file, b, seen);
  if (!base) {
    std::vector<std::string_view> missing;
    for (const spec::ConfigKey& k : spec::kConfigKeys) {
      if (std::find(seen.begin(), seen.end(), k.name) == seen.end()) missing.push_back(k.name);
    }
    if (!missing.empty()) {
      throw Error(fmt::format("{}: missing {} (a file without `base = \"NAME\"` holds every key; "
                              "`rpu config show default` prints them)",
                              file, fmt::join(missing, ", ")));
    }
  }
  b.config.name = top_string(table, "name", file).value_or(std::filesystem::path(file).stem().string());
  b.config.doc = top_string(table, "doc", file).value_or(base ? fmt::format("{} with the changes of {}", *base, file)
                                                             : fmt::format("from {}", file));
}

std::string read_file(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) {
    throw Error(fmt::format("--config {}: no such configuration file, and no named configuration '{}' "
                            "(spec/configs.toml has {}){}",
                            file, file, fmt::join(config_names(), ", "), did_you_mean(file, config_names())));
  }
  return read_input_file(file, "the configuration file", kMaxConfigFileBytes);
}

void apply_set(const Change& change, Builder& b) {
  const std::string& assignment = change.assignment;
  const std::string where = quote_input(change.option);
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw Error(fmt::format("{}: expected key=value", where));
  const std::string name = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const spec::ConfigKey* key = find_key(name);
  if (key == nullptr) throw Error(fmt::format("{}: {}", where, unknown_key(name)));
  if (key->kind == spec::KeyKind::kFormat) {
    b.set(*key, text, where);
    return;
  }
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range) {
    throw Error(fmt::format("{}: {} is outside [{}, {}]", where, text, key->min, key->max));
  }
  if (ec != std::errc() || end != text.data() + text.size() || text.empty()) {
    throw Error(fmt::format("{}: '{}' is not an integer", where, text));
  }
  b.set(*key, value, where);
}


// A TOML basic string: quotes and backslashes escaped, control characters as \uXXXX.
std::string toml_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string value_text(const Entry& e) {
  if (const std::string* s = std::get_if<std::string>(&e.value)) return toml_string(*s);
  return std::to_string(std::get<std::int64_t>(e.value));
}

// The sets, then the latencies of the format, the derived values and the rules.
spec::HardwareConfig finish(Builder& b, const std::vector<Change>& changes) {
  for (const Change& c : changes) apply_set(c, b);
  // What was changed stays with the configuration (`rpu config show`, --stats), so a
  // changed one never reads as the file or the named configuration it started from.
  if (!changes.empty()) {
    std::vector<std::string> options;
    for (const Change& c : changes) options.push_back(c.option);
    b.config.doc = fmt::format("{}; changed by {}", b.config.doc, fmt::join(options, ", "));
  }

  spec::HardwareConfig& c = b.config;
  const int fraction_bits = fp::format_by_name(c.format).fraction_bits;
  const auto f = static_cast<std::size_t>(fraction_bits);
  const auto& latency = spec::kShaderLatencies[spec::kShaderLatenciesByFractionBits.at(f)];
  const auto& tu = spec::kTuLatencies[spec::kTuLatenciesByFractionBits.at(f)];
  const auto& iu = spec::kIuLatencies[spec::kIuLatenciesByFractionBits.at(f)];
  c.latency = latency.value;
  c.tu = tu.value;
  c.iu = iu.value;
  c.latency_format = latency.format;
  c.tu_format = tu.format;
  c.iu_format = iu.format;
  spec::derive(c);
  for (const spec::ConfigRule& rule : spec::kConfigRules) {
    if (rule.holds(c)) continue;
    std::vector<std::string> values;
    std::istringstream names{std::string(rule.names)};
    for (std::string n; names >> n;) {
      for (const Entry& e : entries(c)) {
        if (e.name != n) continue;
        const auto from = b.origin.find(n);
        values.push_back(fmt::format("{} = {}{}", n, value_text(e),
                                     from != b.origin.end() ? " from " + from->second : std::string()));
      }
    }
    throw Error(fmt::format("configuration '{}': {} ({})", c.name, rule.message, fmt::join(values, ", ")));
  }
  return c;
}

}  // namespace

std::vector<Change> set_options(const std::vector<std::string>& sets) {
  std::vector<Change> out;
  for (const std::string& s : sets) out.push_back({s, "--set " + s});
  return out;
}

spec::HardwareConfig resolve(std::string_view name_or_file, const std::vector<std::string>& sets) {
  return resolve_changed(name_or_file, set_options(sets));
}

spec::HardwareConfig resolve_changed(std::string_view name_or_file, const std::vector<Change>& changes) {
  const auto named = std::find_if(spec::kConfigs.begin(), spec::kConfigs.end(),
                                  [&](const spec::HardwareConfig& c) { return c.name == name_or_file; });
  Builder b;
  if (named == spec::kConfigs.end()) {
    const std::string file(name_or_file);
    read_text(read_file(file), file, b);
  } else {
    b.set_from(*named, fmt::format("config '{}'", named->name));
  }
  return finish(b, changes);
}

spec::HardwareConfig parse(std::string_view toml_text, const std::string& source, const std::vector<std::string>& sets) {
  Builder b;
  read_text(toml_text, source, b);
  return finish(b, set_options(sets));
}

std::vector<Entry> entries(const spec::HardwareConfig& c) {
  std::vector<Entry> out;
  for (const spec::ConfigKey& k : spec::kConfigKeys) {
    if (k.kind == spec::KeyKind::kFormat) {
      out.push_back({std::string(k.name), c.format, Entry::Kind::kChoice});
    } else {
      out.push_back({std::string(k.name), k.get(c), Entry::Kind::kChoice});
    }
  }
  for (const spec::DerivedValue& d : spec::kDerivedValues) {
    out.push_back({std::string(d.name), d.get(c), Entry::Kind::kDerived});
  }
  for (const spec::MeasuredValue& m : spec::kMeasuredValues) {
    out.push_back({std::string(m.name), m.get(c), Entry::Kind::kMeasured});
  }
  out.push_back({"latency_format", c.latency_format, Entry::Kind::kMeasured});
  out.push_back({"tu_format", c.tu_format, Entry::Kind::kMeasured});
  out.push_back({"iu_format", c.iu_format, Entry::Kind::kMeasured});
  return out;
}

std::string to_toml(const spec::HardwareConfig& c) {
  std::string out;
  out += fmt::format("name = {}\ndoc = {}\n", toml_string(c.name), toml_string(c.doc));
  std::string group;
  const std::vector<Entry> all = entries(c);
  for (const Entry& e : all) {
    if (e.kind != Entry::Kind::kChoice) continue;
    const std::size_t dot = e.name.find('.');
    const std::string g = dot == std::string::npos ? "" : e.name.substr(0, dot);
    if (g != group) out += fmt::format("\n[{}]\n", g), group = g;
    out += fmt::format("{} = {}\n", e.name.substr(dot == std::string::npos ? 0 : dot + 1), value_text(e));
  }
  out += "\n# Derived (spec/config_keys.toml):\n";
  for (const spec::DerivedValue& d : spec::kDerivedValues) {
    out += fmt::format("#   {} = {}  ({})\n", d.name, d.get(c), d.expr);
  }
  out += fmt::format("# Measured (spec/latencies.toml: latency of {}, tu of {}, iu of {}):\n", c.latency_format,
                     c.tu_format, c.iu_format);
  for (const Entry& e : all) {
    if (e.kind == Entry::Kind::kMeasured && std::holds_alternative<std::int64_t>(e.value)) {
      out += fmt::format("#   {} = {}\n", e.name, value_text(e));
    }
  }
  return out;
}

}  // namespace rpu::config
