#include "sweep/area.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/input_file.hpp"

namespace rpu::sweep {
namespace {

// The records of the checkout the tool was built from; RPU_AREA_RECORDS names another
// file (a copied binary, a file of one's own syntheses).
const nlohmann::json& records() {
  static const nlohmann::json parsed = [] {
    const char* chosen = std::getenv("RPU_AREA_RECORDS");
    const std::string path = chosen != nullptr && *chosen != '\0' ? chosen : RPU_AREA_RECORDS;
    std::string text;
    try {
      text = read_input_file(path, "the synthesis records");
    } catch (const Error& e) {
      throw Error(fmt::format("{} (bench/results/area.json of a checkout; RPU_AREA_RECORDS names the file)", e.what()));
    }
    try {
      return nlohmann::json::parse(text).at("records");
    } catch (const nlohmann::json::exception& e) {
      throw Error(fmt::format("{}: not the synthesis records rtl/flow.py area writes ({})", path, e.what()));
    }
  }();
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

AreaEstimate estimate_area(const spec::HardwareConfig& config, IsectMode mode) {
  AreaEstimate out;
  const nlohmann::json* chip = nullptr;
  for (const nlohmann::json& r : records()) {
    if (r.value("unit", "") == "chip" && r.value("config", "") == "default" && r.value("isect", "") == "woop") chip = &r;
  }
  if (chip == nullptr) return out;
  // Cells of one instance and the instances in the default chip, by unit and the unit it is in.
  std::map<std::pair<std::string, std::string>, std::pair<double, double>> unit;
  for (const nlohmann::json& u : (*chip)["units"]) {
    unit[{u.value("unit", ""), u.value("within", "")}] = {u["cells"].get<double>(), u["instances"].get<double>(),};
    if (u.value("unit", "") == "register file bank") out.ram_bits = u["ram_bits"].get<std::uint64_t>();
  }
  // The register files as the default chip holds them (banked, one copy per read port),
  // per bit of architectural state: threads x registers x 4 lanes x 32 bits.
  const spec::HardwareConfig& base = *std::find_if(spec::kConfigs.begin(), spec::kConfigs.end(),
                                                   [](const spec::HardwareConfig& c) { return c.name == "default"; });
  const auto state_bits = [](const spec::HardwareConfig& c) {
    return static_cast<double>(c.shader_cores) * c.threads_per_core * c.registers * 4 * 32;
  };
  const double copies = static_cast<double>(out.ram_bits) * unit[{"register file bank", "shader core"}].second /
                        state_bits(base);
  out.ram_bits = 8 * ((config.node_cache.bytes + config.triangle_cache.bytes) *
                          static_cast<std::uint64_t>(config.ray_caches) +
                      config.data_cache.bytes * static_cast<std::uint64_t>(config.shader_cores)) +
                 static_cast<std::uint64_t>(std::llround(copies * state_bits(config)));

  const fp::Format format = fp::format_by_name(config.format);
  const std::string isect(isect_name(mode));
  // A unit's cells in the format against fp32, from their own synthesis.
  const auto ratio = [&](const std::string& name, const std::string& fp32_name) -> std::optional<double> {
    const auto mine = unit_cells(name, format), fp32 = unit_cells(fp32_name, fp::kFp32);
    if (!mine || !fp32) return std::nullopt;
    return static_cast<double>(*mine) / static_cast<double>(*fp32);
  };
  const auto fma = ratio("fma", "fma"), misc = ratio("misc", "misc"), divsqrt = ratio("divsqrt", "divsqrt");
  const auto tu = ratio("tu_" + isect, "tu_woop"), iu = ratio("iu_" + isect, "iu_woop");
  if (!fma || !misc || !divsqrt || !tu || !iu) return out;
  const auto cells = [&](const char* name, const char* within) { return unit[{name, within}].first; };
  const auto count = [&](const char* name, const char* within) { return unit[{name, within}].second; };
  const double cores = count("shader core", "chip");
  // A shader core with its FP units (datapath fma and misc, the SFU's divsqrt) in the
  // format, and the configuration's dividers (sfu_units of each of sfu_threads sfus) in
  // place of the default chip's.
  const double dividers = static_cast<double>(config.sfu_units) * config.sfu_threads;
  const double core = cells("shader core", "chip") +
                      count("fma", "vector datapath") / cores * cells("fma", "vector datapath") * (*fma - 1.0) +
                      count("misc", "vector datapath") / cores * cells("misc", "vector datapath") * (*misc - 1.0) +
                      (dividers * *divsqrt - count("divsqrt", "special-function unit") / cores) *
                          cells("divsqrt", "special-function unit");
  const double tu_cells = cells("traversal unit", "ray unit") * *tu;
  const double iu_cells = cells("intersection unit", "ray unit") * *iu;
  const double rest = cells("chip", "") - cores * cells("shader core", "chip") -
                      count("traversal unit", "ray unit") * cells("traversal unit", "ray unit") -
                      count("intersection unit", "ray unit") * cells("intersection unit", "ray unit");
  out.logic_cells = static_cast<std::uint64_t>(std::llround(rest + config.shader_cores * core +
                                                            config.traversal_units * tu_cells +
                                                            config.intersection_units * iu_cells));
  return out;
}

}  // namespace rpu::sweep
