#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <tuple>

#include "rpu/harness/mem.hpp"
#include "rpu/streams.hpp"

// The memory system's shape as its harness's ports have it (sim/rpu_mem_system.sv,
// generated into rpu/harness/mem.hpp): three caches, each behind cache ports and
// traversal-unit (in-order) ports, port p of cache c at index c * ports + p.
namespace rpu::sim {

inline constexpr std::size_t kMemCaches = std::tuple_size_v<decltype(harness::Mem::Outputs::counters)>;
inline constexpr std::size_t kRaw = std::tuple_size_v<decltype(harness::Mem::Inputs::req)>;
inline constexpr std::size_t kInOrder = std::tuple_size_v<decltype(harness::Mem::Inputs::mem_req)>;
inline constexpr std::size_t kRawPorts = kRaw / kMemCaches;          // cache ports per cache
inline constexpr std::size_t kInOrderPorts = kInOrder / kMemCaches;  // traversal-unit ports per cache
inline constexpr const char* kCacheNames[kMemCaches] = {"node", "triangle", "data"};  // CacheId 0, 1, 2

inline std::uint32_t cache_sets(const streams::CacheGeometry& g) { return g.bytes / (streams::kDramLineBytes * g.ways); }

}  // namespace rpu::sim
