#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

namespace rpu::fuzz {

// The largest size of each built-in generator a fuzz target builds.
struct GeneratorLimits {
  long long balls, tetra, cornell, stadium, scattered;
};

// True for {"procedural": {"generator": G, "size": N}} with N above `limits`: such a
// scene is a legitimate cost, not a finding, and would stall the run (balls:5 is 15
// million triangles). The generators' own size limits are unit-tested.
inline bool asks_for_large_scene(std::string_view text, const GeneratorLimits& limits) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("procedural")) return false;
  const nlohmann::json& p = j["procedural"];
  if (!p.is_object() || !p.contains("size") || !p["size"].is_number_integer() || !p.contains("generator")) {
    return false;
  }
  const nlohmann::json& g = p["generator"];
  const long long n = p["size"].get<long long>();
  return (g == "balls" && n > limits.balls) || (g == "tetra" && n > limits.tetra) ||
         (g == "cornell" && n > limits.cornell) || (g == "stadium" && n > limits.stadium) ||
         (g == "scattered" && n > limits.scattered);
}

}  // namespace rpu::fuzz
