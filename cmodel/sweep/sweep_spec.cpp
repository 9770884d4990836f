#include "sweep/sweep_spec.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <span>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "common/did_you_mean.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "config/config.hpp"
#include "fp/format.hpp"
#include "render/selection.hpp"
#include "rpu/spec.hpp"
#include "scene/procedural.hpp"

namespace rpu::sweep {
namespace {

namespace fs = std::filesystem;

// The axes a grid spans and a [[point]] sets, in the order the grid nests them (the
// last varies fastest).
constexpr std::string_view kAxes[] = {"scene",    "transform", "config", "set",    "format",
                                      "isect",    "firmware",  "select", "spp",    "fidelity"};
// Besides the axes, a grid or point may set its own image size.
constexpr std::string_view kGridKeys[] = {"scene",  "transform", "config", "set",      "format", "isect",
                                          "firmware", "select",  "spp",    "fidelity", "width",  "height"};
// More points than a cluster's job arrays would take in a week of seconds each.
constexpr std::size_t kMaxPoints = 100'000;
constexpr std::string_view kTopKeys[] = {"name",      "width",        "height", "max_depth", "seed",
                                         "leak_rays", "extreme_rays", "hit_check", "grid",     "point"};

std::string where(const std::string& source, const toml::node& node) {
  return fmt::format("{}:{}:{}", source, node.source().begin.line, node.source().begin.column);
}

std::vector<std::string_view> names_of(std::span<const std::string_view> names) {
  return {names.begin(), names.end()};
}

void check_keys(const toml::table& table, std::span<const std::string_view> known, const std::string& source,
                std::string_view context) {
  for (const auto& [key, node] : table) {
    if (std::find(known.begin(), known.end(), key.str()) != known.end()) continue;
    throw Error(fmt::format("{}: unknown key '{}'{} (known: {}){}", where(source, node), quote_input(key.str()), context,
                            fmt::join(known, ", "), did_you_mean(key.str(), names_of(known))));
  }
}

std::int64_t integer(const toml::node& node, std::string_view key, std::int64_t lo, std::int64_t hi,
                     const std::string& source) {
  const auto* value = node.as_integer();
  if (value == nullptr) throw Error(fmt::format("{}: {} must be an integer", where(source, node), key));
  if (value->get() < lo || value->get() > hi) {
    throw Error(fmt::format("{}: {} = {} is outside [{}, {}]", where(source, node), key, value->get(), lo, hi));
  }
  return value->get();
}

// One value of an axis, before it is checked: the text or texts and where it was given.
struct Value {
  std::vector<std::string> texts;  // one, or several for `set` and `firmware`
  std::int64_t number = 0;         // spp
  std::string where;
};

// The alternatives an axis names: a scalar is one, an array lists them. For `set` and
// `firmware` an alternative is a string (one item; "" for none) or an array of strings.
std::vector<Value> alternatives(const toml::node& node, std::string_view axis, const std::string& source,
                                bool list_allowed) {
  const bool multi = axis == "set" || axis == "firmware";
  auto one = [&](const toml::node& n) {
    Value v;
    v.where = where(source, n);
    if (axis == "spp") {
      v.number = integer(n, axis, 1, 65536, source);
      return v;
    }
    if (const auto* s = n.as_string()) {
      if (!s->get().empty() || !multi) v.texts.push_back(s->get());
      return v;
    }
    if (const auto* a = n.as_array(); a != nullptr && multi) {
      for (const toml::node& item : *a) {
        const auto* s = item.as_string();
        if (s == nullptr || s->get().empty()) {
          throw Error(fmt::format("{}: each item of a {} alternative must be a non-empty string", where(source, item),
                                  axis));
        }
        v.texts.push_back(s->get());
      }
      return v;
    }
    throw Error(fmt::format("{}: {} must be {}", v.where, axis,
                            multi ? "a string or an array of strings" : "a string"));
  };
  if (const auto* a = node.as_array(); a != nullptr && list_allowed) {
    if (a->empty()) throw Error(fmt::format("{}: {} lists no values", where(source, node), axis));
    std::vector<Value> out;
    for (const toml::node& item : *a) out.push_back(one(item));
    return out;
  }
  return {one(node)};
}

// A path of the sweep file, made absolute against its directory; it must exist.
std::string existing_path(const std::string& text, const fs::path& base_dir, const std::string& at,
                          std::string_view what) {
  const fs::path path = fs::path(text).is_absolute() ? fs::path(text) : base_dir / text;
  try {
    check_input_file(path);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {} '{}': {}", at, what, text, e.what()));
  }
  return fs::absolute(path).lexically_normal().string();
}

struct Settings {
  int width = 64, height = 64, max_depth = 5;
  std::uint64_t seed = 1;
};

// The axes of one grid or point, checked; each a list of alternatives. Its image size,
// when it sets one.
struct Axes {
  std::vector<Value> values[std::size(kAxes)];
  std::optional<int> width, height;
};

std::string slug(std::string_view scene) {
  std::string name = fs::path(scene).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
  }
  return name;
}

std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

class Expander {
 public:
  Expander(const std::string& source, fs::path base_dir, Settings settings, Spec& spec)
      : source_(source), base_dir_(std::move(base_dir)), settings_(settings), spec_(spec) {}

  Axes read_axes(const toml::table& table, bool grid) {
    check_keys(table, kGridKeys, source_, grid ? " in [grid]" : " in a [[point]]");
    Axes axes;
    if (const toml::node* n = table.get("width")) axes.width = static_cast<int>(integer(*n, "width", 1, 16384, source_));
    if (const toml::node* n = table.get("height")) axes.height = static_cast<int>(integer(*n, "height", 1, 16384, source_));
    for (std::size_t i = 0; i < std::size(kAxes); ++i) {
      const toml::node* node = table.get(kAxes[i]);
      if (node != nullptr) {
        axes.values[i] = alternatives(*node, kAxes[i], source_, grid || kAxes[i] == "set" || kAxes[i] == "firmware");
        // In a [[point]], `set` and `firmware` hold one alternative: an array is its items.
        if (!grid && (kAxes[i] == "set" || kAxes[i] == "firmware") && node->is_array()) {
          Value v;
    v.where = where(source_, *node);
          for (const Value& a : axes.values[i]) v.texts.insert(v.texts.end(), a.texts.begin(), a.texts.end());
          axes.values[i] = {v};
        }
        continue;
      }
      if (kAxes[i] == "scene") {
        throw Error(fmt::format("{}:{}:{}: {} names no scene", source_, table.source().begin.line,
                                table.source().begin.column, grid ? "[grid]" : "a [[point]]"));
      }
      Value v;
    v.where = source_;
      if (kAxes[i] == "spp") v.number = 1;
      if (kAxes[i] == "config") v.texts = {"default"};
      if (kAxes[i] == "isect") v.texts = {"woop"};
      if (kAxes[i] == "select") v.texts = {"1"};
      if (kAxes[i] == "fidelity") v.texts = {"functional"};
      axes.values[i] = {v};
    }
    return axes;
  }

  void expand(const Axes& axes) {
    std::size_t count = 1;
    for (const std::vector<Value>& v : axes.values) count = std::min(count * v.size(), kMaxPoints + 1);
    if (count + spec_.points.size() > kMaxPoints) {
      throw Error(fmt::format("{}: the sweep has more than {} points; split it", source_, kMaxPoints));
    }
    Point p;
    p.width = axes.width.value_or(settings_.width);
    p.height = axes.height.value_or(settings_.height);
    p.max_depth = settings_.max_depth;
    p.seed = settings_.seed;
    nest(axes, 0, p);
  }

 private:
  void nest(const Axes& axes, std::size_t axis, Point& p) {
    if (axis == std::size(kAxes)) {
      add(p);
      return;
    }
    for (const Value& v : axes.values[axis]) {
      Point q = p;
      set_axis(kAxes[axis], v, q);
      nest(axes, axis + 1, q);
    }
  }

  void set_axis(std::string_view axis, const Value& v, Point& p) {
    const std::string text = v.texts.empty() ? "" : v.texts.front();
    if (axis == "scene") {
      p.scene = scene(text, v.where);
    } else if (axis == "transform") {
      try {
        parse_transform(text);
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", v.where, e.what()));
      }
      p.transform = text;
    } else if (axis == "config") {
      p.config = text.ends_with(".toml") ? existing_path(text, base_dir_, v.where, "configuration") : text;
      config_where_ = v.where;
    } else if (axis == "set") {
      p.sets = v.texts;
      sets_where_ = v.where;
    } else if (axis == "format") {
      if (!text.empty()) {
        try {
          p.format = fp::format_label(fp::format_by_name(text));
        } catch (const Error& e) {
          throw Error(fmt::format("{}: {}", v.where, e.what()));
        }
      }
    } else if (axis == "isect") {
      if (text != "woop" && text != "watertight") {
        throw Error(fmt::format("{}: isect '{}' is neither woop nor watertight", v.where, text));
      }
      p.isect = text;
    } else if (axis == "firmware") {
      p.firmware.clear();
      for (const std::string& f : v.texts) p.firmware.push_back(existing_path(f, base_dir_, v.where, "firmware"));
    } else if (axis == "select") {
      try {
        p.select = to_string(parse_selection(text));
      } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", v.where, e.what()));
      }
    } else if (axis == "spp") {
      p.spp = static_cast<int>(v.number);
    } else if (std::find(std::begin(kFidelities), std::end(kFidelities), text) == std::end(kFidelities)) {
      throw Error(fmt::format("{}: fidelity '{}' is not one of {}{}", v.where, text, fmt::join(kFidelities, ", "),
                              did_you_mean(text, names_of(kFidelities))));
    } else {
      p.fidelity = text;
    }
  }

  std::string scene(const std::string& text, const std::string& at) {
    if (is_builtin_scene(text)) return text;
    return existing_path(text, base_dir_, at, "scene");
  }

  // The point's configuration, resolved once per distinct one: an unknown name or key,
  // a bad value or a broken rule is an error at the line that chose it.
  void check_config(Point& p) {
    std::vector<std::string> sets = p.sets;
    if (!p.format.empty()) sets.push_back("format=" + p.format);
    const std::string key = fmt::format("{}\n{}", p.config, fmt::join(sets, "\n"));
    auto found = resolved_.find(key);
    if (found == resolved_.end()) {
      try {
        const spec::HardwareConfig c = config::resolve(p.config, sets);
        found = resolved_.emplace(key, fp::format_label(fp::format_by_name(c.format))).first;
      } catch (const Error& e) {
        throw Error(fmt::format("{}: config '{}'{}: {}", p.sets.empty() ? config_where_ : sets_where_, p.config,
                                p.sets.empty() ? "" : fmt::format(" with set {}", fmt::join(p.sets, ", ")), e.what()));
      }
    }
    p.format = found->second;
  }

  void add(Point p) {
    Point reference;
    reference.scene = p.scene;
    reference.fidelity = "reference";
    reference.width = p.width;
    reference.height = p.height;
    reference.spp = p.spp;
    reference.max_depth = p.max_depth;
    reference.seed = p.seed;
    reference.transform = p.transform;
    reference.config.clear();
    reference.isect.clear();
    reference.id = id_of(reference);
    if (seen_.insert(reference.id).second) spec_.references.push_back(reference);
    if (p.fidelity == "reference") return;
    check_config(p);
    p.reference = reference.id;
    p.id = id_of(p);
    if (seen_.insert(p.id).second) spec_.points.push_back(std::move(p));
  }

  std::string id_of(const Point& p) const {
    // A transformed point is measured by its image alone (sweep-point runs no ray checks).
    const std::string checks = p.fidelity == "reference" || !p.transform.empty()
                                   ? ""
                                   : fmt::format("{} {} {}", spec_.leak_rays, spec_.hit_check, spec_.extreme_rays);
    return fmt::format("{}-{}-{:08x}", p.fidelity, slug(p.scene),
                       static_cast<std::uint32_t>(fnv1a(p.canonical() + checks) >> 32));
  }

  const std::string& source_;
  fs::path base_dir_;
  Settings settings_;
  Spec& spec_;
  std::string config_where_, sets_where_;
  std::map<std::string, std::string> resolved_;  // config and sets -> format label
  std::set<std::string> seen_;
};

}  // namespace

Transform parse_transform(std::string_view text) {
  Transform t;
  if (text.empty()) return t;
  const auto number = [&](std::string_view rest, auto& value) {
    const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
    return ec == std::errc{} && end == rest.data() + rest.size();
  };
  if (text.starts_with("scale:") && number(text.substr(6), t.scale_exponent) && t.scale_exponent >= -100 &&
      t.scale_exponent <= 100 && t.scale_exponent != 0) {
    return t;
  }
  if (text.starts_with("translate:") && number(text.substr(10), t.offset) && std::isfinite(t.offset) &&
      std::abs(t.offset) <= 1e30 && t.offset != 0.0) {
    return t;
  }
  throw Error(fmt::format("transform '{}' is neither scale:K (K a non-zero whole number in [-100, 100]) nor "
                          "translate:D (D a non-zero number within 1e30)",
                          text));
}

std::string Point::canonical() const {
  std::string out = fmt::format("scene {}\nfidelity {}\nwidth {}\nheight {}\nspp {}\nmax_depth {}\nseed {}\n", scene,
                                fidelity, width, height, spp, max_depth, seed);
  if (!transform.empty()) out += fmt::format("transform {}\n", transform);
  if (fidelity == "reference") return out;
  out += fmt::format("config {}\nset {}\nformat {}\nisect {}\nfirmware {}\n", config, fmt::join(sets, " "), format,
                     isect, fmt::join(firmware, " "));
  if (select != "1") out += fmt::format("select {}\n", select);
  return out;
}

std::vector<std::string> Point::render_args() const {
  std::vector<std::string> args = {scene,        "--backend",  fidelity, "--width", std::to_string(width),
                                   "--height",   std::to_string(height), "--spp", std::to_string(spp),
                                   "--max-depth", std::to_string(max_depth), "--seed", std::to_string(seed)};
  const Transform t = parse_transform(transform);
  if (t.scale_exponent != 0) args.insert(args.end(), {"--scale-exponent", std::to_string(t.scale_exponent)});
  if (t.offset != 0.0) {
    const std::string d = fmt::format("{}", t.offset);
    args.insert(args.end(), {"--translate", d, d, d});
  }
  if (fidelity == "reference") return args;
  args.insert(args.end(), {"--config", config, "--format", format, "--isect", isect});
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  if (select != "1") args.insert(args.end(), {"--select", select});
  if (!firmware.empty()) {
    args.emplace_back("--firmware");
    args.insert(args.end(), firmware.begin(), firmware.end());
  }
  return args;
}

Spec parse_spec(std::string_view text, const std::string& source, const fs::path& base_dir) {
  toml::table table;
  try {
    table = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw Error(fmt::format("{}:{}:{}: {}", source, e.source().begin.line, e.source().begin.column, e.description()));
  }
  check_keys(table, kTopKeys, source, "");
  Spec spec;
  Settings settings;
  spec.name = fs::path(source).stem().string();
  if (const toml::node* n = table.get("name")) {
    if (!n->is_string() || n->as_string()->get().empty()) {
      throw Error(fmt::format("{}: name must be a non-empty string", where(source, *n)));
    }
    spec.name = n->as_string()->get();
  }
  if (const toml::node* n = table.get("width")) settings.width = static_cast<int>(integer(*n, "width", 1, 16384, source));
  if (const toml::node* n = table.get("height")) settings.height = static_cast<int>(integer(*n, "height", 1, 16384, source));
  if (const toml::node* n = table.get("max_depth")) settings.max_depth = static_cast<int>(integer(*n, "max_depth", 0, 64, source));
  if (const toml::node* n = table.get("seed")) settings.seed = static_cast<std::uint64_t>(integer(*n, "seed", 0, INT64_MAX, source));
  if (const toml::node* n = table.get("leak_rays")) spec.leak_rays = static_cast<std::uint32_t>(integer(*n, "leak_rays", 0, 10'000'000, source));
  if (const toml::node* n = table.get("extreme_rays")) spec.extreme_rays = static_cast<std::uint32_t>(integer(*n, "extreme_rays", 0, 1'000'000, source));
  if (const toml::node* n = table.get("hit_check")) {
    if (!n->is_boolean()) throw Error(fmt::format("{}: hit_check must be true or false", where(source, *n)));
    spec.hit_check = n->as_boolean()->get();
  }
  Expander expander(source, base_dir, settings, spec);
  if (const toml::node* n = table.get("grid")) {
    // One [grid], or several [[grid]]s.
    std::vector<const toml::table*> grids;
    if (const toml::array* a = n->as_array()) {
      for (const toml::node& g : *a) grids.push_back(g.as_table());
    } else {
      grids.push_back(n->as_table());
    }
    for (const toml::table* g : grids) {
      if (g == nullptr) throw Error(fmt::format("{}: grid must be a table ([grid] or [[grid]])", where(source, *n)));
      expander.expand(expander.read_axes(*g, true));
    }
  }
  if (const toml::node* n = table.get("point")) {
    const toml::array* points = n->as_array();
    if (points == nullptr) throw Error(fmt::format("{}: point must be an array of tables ([[point]])", where(source, *n)));
    for (const toml::node& p : *points) {
      if (!p.is_table()) throw Error(fmt::format("{}: each point must be a table ([[point]])", where(source, p)));
      expander.expand(expander.read_axes(*p.as_table(), false));
    }
  }
  if (spec.references.empty()) {
    throw Error(fmt::format("{}: the sweep has no points: give a [grid] or [[point]] tables", source));
  }
  return spec;
}

Spec read_spec(const fs::path& file) {
  return parse_spec(read_input_file(file, "the sweep file", std::uintmax_t{1} << 20), file.string(),
                    fs::absolute(file).parent_path());
}

}  // namespace rpu::sweep
