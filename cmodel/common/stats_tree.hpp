#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace rpu {

// A report as data: named values (integers, reals, text) and named groups of them,
// nested to any depth, in the order they were added; a list holds unnamed groups (one
// per unit). A backend fills one for its frame (device::DeviceStats::report) and the
// writers below show whatever it holds, so a new metric or group is one line where it
// is known: report.group("run").set("commit", hash).
class StatsTree {
 public:
  using Value = std::variant<std::int64_t, std::uint64_t, double, std::string>;
  enum class Kind { kGroup, kList, kValue };

  // In a group: the value `name` (a set of a name already there replaces its value in
  // place). Returns the group, so that sets chain.
  template <class T>
  StatsTree& set(std::string_view name, const T& value) {
    if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
      return put(name, Value(std::in_place_type<std::int64_t>, value));
    } else if constexpr (std::is_integral_v<T>) {
      return put(name, Value(std::in_place_type<std::uint64_t>, value));
    } else if constexpr (std::is_floating_point_v<T>) {
      return put(name, Value(std::in_place_type<double>, value));
    } else {
      return put(name, Value(std::in_place_type<std::string>, value));
    }
  }
  // In a group: the group or list `name`, added at the end if there is none.
  StatsTree& group(std::string_view name) { return child(name, Kind::kGroup); }
  StatsTree& list(std::string_view name) { return child(name, Kind::kList); }
  // In a list: a new group at its end.
  StatsTree& add();

  Kind kind() const { return kind_; }
  const std::string& name() const { return name_; }  // empty for a list's groups
  const Value& value() const { return value_; }
  const std::vector<StatsTree>& children() const { return children_; }
  // The node at a dotted path ("caches.node.hit_rate"; a list's groups by index,
  // "shader_cores.0.busy"), or null.
  const StatsTree* find(std::string_view path) const;
  // The number at `path`; rpu::Error naming the path if there is none.
  double number(std::string_view path) const;

 private:
  StatsTree& put(std::string_view name, Value value);
  StatsTree& child(std::string_view name, Kind kind);

  Kind kind_ = Kind::kGroup;
  std::string name_;
  Value value_;
  std::vector<StatsTree> children_;
};

// JSON: a group is an object (keys sorted), a list an array, integers stay integers.
std::string stats_json(const StatsTree& tree);
// One wide row, so that many runs join into one table (a spreadsheet, pandas): a header
// line of dotted paths (caches.node.hit_rate), then one line of values, both in the
// tree's order.
std::string stats_csv_row(const StatsTree& tree);

// By the file's extension, .json (stats_json) or .csv (stats_csv_row); rpu::Error for
// another. Written through an OutputFile.
void write_stats(const StatsTree& tree, const std::filesystem::path& path);

}  // namespace rpu
