#include "sweep/area.hpp"

#include <string>

#include <nlohmann/json.hpp>

#include "sweep/area_records.hpp"

namespace rpu::sweep {
namespace {

const nlohmann::json& records() {
  static const nlohmann::json parsed = nlohmann::json::parse(kAreaRecords).at("records");
  return parsed;
}

std::string_view isect_name(IsectMode mode) { return mode == IsectMode::kWatertight ? "watertight" : "woop"; }

// The latest record of `unit` in `format` of the base design: the IU's micro-program, the
// TU with one ray slot.
std::optional<std::uint64_t> unit_cells(std::string_view unit, const fp::Format& format) {
  std::optional<std::uint64_t> cells;
  for (const nlohmann::json& r : records()) {
    if (r.value("unit", "") != unit || !r.contains("exponent_bits")) continue;
    if (r["exponent_bits"] != format.exponent_bits || r["fraction_bits"] != format.fraction_bits) continue;
    const std::string design = r.value("design", "");
    if (!design.empty() && !design.starts_with("micro-program")) continue;
    if (r.value("slots", 1) != 1) continue;
    cells = r["cells"].get<std::uint64_t>();
  }
  return cells;
}

}  // namespace

std::optional<std::uint64_t> datapath_cells(fp::Format format, IsectMode mode) {
  std::uint64_t sum = 0;
  const std::string isect(isect_name(mode));
  for (const std::string& unit : {std::string("fma"), std::string("misc"), std::string("divsqrt"), "iu_" + isect,
                                  "tu_" + isect}) {
    const std::optional<std::uint64_t> cells = unit_cells(unit, format);
    if (!cells) return std::nullopt;
    sum += *cells;
  }
  return sum;
}

std::optional<std::uint64_t> chip_cells(std::string_view config, IsectMode mode) {
  std::optional<std::uint64_t> cells;
  for (const nlohmann::json& r : records()) {
    if (r.value("unit", "") != "chip" || r.value("config", "") != config || r.value("isect", "") != isect_name(mode)) {
      continue;
    }
    for (const nlohmann::json& u : r["units"]) {
      if (u.value("depth", -1) == 0) cells = u["cells"].get<std::uint64_t>();
    }
  }
  return cells;
}

}  // namespace rpu::sweep
