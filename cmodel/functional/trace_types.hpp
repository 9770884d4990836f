#pragma once

#include <array>
#include <cstdint>
#include <limits>

namespace rpu::functional {

enum class TraceMode : std::uint8_t {
  kClosest,  // the nearest hit in (t_min, t_max)
  kAny,      // any hit in (t_min, t_max): shadow rays; stops at the first
};

// A ray as the shader hands it to the traversal unit: fp32 values, rounded into the
// configured format by the unit (docs/traversal.md §1).
struct TraceRay {
  std::array<float, 3> origin{};
  std::array<float, 3> direction{};
  float t_min = 0.0f;
  float t_max = std::numeric_limits<float>::infinity();
};

// Work done for one ray: what cost heatmaps and the cycle model count.
struct TraceCounters {
  std::uint32_t nodes = 0;   // kd nodes fetched (inner and leaf)
  std::uint32_t leaves = 0;  // leaves fetched, empty ones included
  std::uint32_t tests = 0;   // ray/triangle tests in the intersection unit
};

// The hit record. t, u, v are the unit's format values widened exactly to fp32; u and v
// weight the triangle's second and third vertex. Meaningful only when hit is true.
struct TraceHit {
  bool hit = false;
  float t = 0.0f, u = 0.0f, v = 0.0f;
  std::uint32_t prim = 0;  // triangle index
  TraceCounters counters;
};

}  // namespace rpu::functional
