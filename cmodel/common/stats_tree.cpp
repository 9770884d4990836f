#include "common/stats_tree.hpp"

#include <algorithm>
#include <charconv>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/output_file.hpp"

namespace rpu {

namespace {

using nlohmann::json;

json scalar_json(const StatsTree::Value& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

// nlohmann::json's objects sort their keys: the JSON and its CSV keep the order they
// have always had, whatever order a backend adds its values in.
json to_json(const StatsTree& t) {
  switch (t.kind()) {
    case StatsTree::Kind::kValue: return scalar_json(t.value());
    case StatsTree::Kind::kList: {
      json a = json::array();
      for (const StatsTree& c : t.children()) a.push_back(to_json(c));
      return a;
    }
    case StatsTree::Kind::kGroup: break;
  }
  json o = json::object();
  for (const StatsTree& c : t.children()) o[c.name()] = to_json(c);
  return o;
}

void row_of(const StatsTree& t, const std::string& path, std::vector<std::string>& names,
            std::vector<std::string>& values) {
  if (t.kind() == StatsTree::Kind::kValue) {
    names.push_back(csv_field(path));
    // Text always quoted; numbers as the JSON writes them.
    const auto* text = std::get_if<std::string>(&t.value());
    values.push_back(text ? csv_field(*text, true) : scalar_json(t.value()).dump());
    return;
  }
  for (std::size_t i = 0; i < t.children().size(); ++i) {
    const StatsTree& c = t.children()[i];
    const std::string name = t.kind() == StatsTree::Kind::kList ? std::to_string(i) : c.name();
    row_of(c, path.empty() ? name : path + '.' + name, names, values);
  }
}

}  // namespace

StatsTree& StatsTree::add() {
  if (kind_ != Kind::kList) throw Error(fmt::format("statistics: add() on '{}', which is not a list", name_));
  children_.emplace_back();
  return children_.back();
}

StatsTree& StatsTree::put(std::string_view name, Value value) {
  StatsTree& c = child(name, Kind::kValue);
  c.value_ = std::move(value);
  return *this;
}

StatsTree& StatsTree::child(std::string_view name, Kind kind) {
  if (kind_ != Kind::kGroup) throw Error(fmt::format("statistics: '{}' in '{}', which is not a group", name, name_));
  const auto it = std::find_if(children_.begin(), children_.end(), [&](const StatsTree& c) { return c.name_ == name; });
  if (it != children_.end()) {
    if (it->kind_ != kind) throw Error(fmt::format("statistics: '{}' is already there as another kind", name));
    return *it;
  }
  StatsTree& c = children_.emplace_back();
  c.kind_ = kind;
  c.name_ = std::string(name);
  return c;
}

const StatsTree* StatsTree::find(std::string_view path) const {
  const StatsTree* node = this;
  while (node && !path.empty()) {
    const std::size_t dot = path.find('.');
    const std::string_view part = path.substr(0, dot);
    path = dot == std::string_view::npos ? std::string_view() : path.substr(dot + 1);
    const StatsTree* next = nullptr;
    if (node->kind_ == Kind::kList) {
      std::size_t i = 0;
      const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), i);
      if (error == std::errc() && end == part.data() + part.size() && i < node->children_.size()) {
        next = &node->children_[i];
      }
    } else {
      for (const StatsTree& c : node->children_) {
        if (c.name_ == part) next = &c;
      }
    }
    node = next;
  }
  return node;
}

double StatsTree::number(std::string_view path) const {
  const StatsTree* node = find(path);
  if (!node || node->kind_ != Kind::kValue || std::holds_alternative<std::string>(node->value_)) {
    throw Error(fmt::format("statistics: no number at '{}'", path));
  }
  if (const auto* i = std::get_if<std::int64_t>(&node->value_)) return static_cast<double>(*i);
  if (const auto* u = std::get_if<std::uint64_t>(&node->value_)) return static_cast<double>(*u);
  return std::get<double>(node->value_);
}

std::string stats_json(const StatsTree& tree) { return to_json(tree).dump(2) + '\n'; }

std::string stats_csv_row(const StatsTree& tree) {
  std::vector<std::string> names, values;
  row_of(tree, "", names, values);
  return fmt::format("{}\n{}\n", fmt::join(names, ","), fmt::join(values, ","));
}

void write_stats(const StatsTree& tree, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext != ".json" && ext != ".csv") {
    throw Error(fmt::format("statistics file '{}': the extension must be .json or .csv", path.string()));
  }
  OutputFile file(path);
  file.stream() << (ext == ".json" ? stats_json(tree) : stats_csv_row(tree));
  file.commit();
}

}  // namespace rpu
