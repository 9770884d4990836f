#include "cycle/cycle_stats.hpp"

#include <algorithm>
#include <ostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/error.hpp"

namespace rpu::cycle {

namespace {

using nlohmann::json;

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

json cache_json(const CacheStats& c) {
  return {{"accesses", c.accesses}, {"hits", c.hits},         {"merged", c.merged},
          {"misses", c.misses},     {"writes", c.writes},     {"hit_rate", c.hit_rate()},
          {"mshr_wait_cycles", c.mshr_wait_cycles}};
}

json stats_json(const CycleStats& s, const functional::ShaderStats& shader) {
  const auto cycles = static_cast<double>(s.cycles);
  json j;
  j["config"] = s.config;
  j["clock_mhz"] = s.clock_mhz;
  j["cycles"] = s.cycles;
  j["frame_seconds"] = s.frame_seconds();
  j["fps"] = ratio(1.0, s.frame_seconds());
  j["host_seconds"] = s.host_seconds;
  j["simulated_cycles_per_host_second"] = ratio(cycles, s.host_seconds);
  j["rays"] = {{"closest", s.closest_rays}, {"any", s.any_rays}, {"total", s.closest_rays + s.any_rays}};
  json by_class;
  for (std::size_t k = 0; k < spec::isa::kClassNames.size(); ++k) by_class[std::string(spec::isa::kClassNames[k])] = shader.retired[k];
  std::uint64_t issues = 0;
  json cores = json::array();
  for (const ShaderCoreTime& t : s.cores) {
    issues += t.chunk_issues;
    cores.push_back({{"busy", t.busy},
                     {"wait_trace", t.wait_trace},
                     {"wait_memory", t.wait_memory},
                     {"wait_dependency", t.wait_dependency},
                     {"idle", t.idle},
                     {"chunk_issues", t.chunk_issues},
                     {"utilisation", ratio(static_cast<double>(t.busy), cycles)}});
  }
  j["instructions"] = {{"thread", s.thread_instructions},
                       {"chunk_issues", issues},
                       {"ipc_per_core", ratio(static_cast<double>(issues), cycles * static_cast<double>(s.cores.size()))},
                       {"thread_ipc", ratio(static_cast<double>(s.thread_instructions), cycles)},
                       {"simd_efficiency", ratio(static_cast<double>(s.thread_instructions),
                                                 static_cast<double>(shader.lanes_issued))},
                       {"by_class", by_class}};
  j["shader_cores"] = cores;
  std::uint64_t steps = 0, tests = 0;
  json tus = json::array();
  for (const TraversalUnitTime& t : s.tus) {
    steps += t.inner + t.leaves;
    tus.push_back({{"busy", t.busy},   {"wait_memory", t.wait_memory}, {"wait_iu", t.wait_iu}, {"idle", t.idle},
                   {"rays", t.rays},   {"inner_nodes", t.inner},       {"leaves", t.leaves}, {"prim_refs", t.refs},
                   {"tests", t.tests}, {"pops", t.pops},
                   {"utilisation", ratio(static_cast<double>(t.busy), cycles)}});
  }
  j["traversal_units"] = tus;
  j["tu_steps_per_cycle"] = ratio(static_cast<double>(steps), cycles);
  json ius = json::array();
  for (const IntersectionUnitTime& t : s.ius) {
    tests += t.tests;
    ius.push_back({{"tests", t.tests}, {"busy", t.busy}, {"utilisation", ratio(static_cast<double>(t.busy), cycles)}});
  }
  j["intersection_units"] = ius;
  j["iu_tests_per_cycle"] = ratio(static_cast<double>(tests), cycles);
  j["caches"] = {{"node", cache_json(s.node_cache)},
                 {"triangle", cache_json(s.triangle_cache)},
                 {"data", cache_json(s.data_cache)}};
  const double bytes = static_cast<double>(s.dram.bytes_read + s.dram.bytes_written);
  j["dram"] = {{"reads", s.dram.reads},
               {"writes", s.dram.writes},
               {"bytes_read", s.dram.bytes_read},
               {"bytes_written", s.dram.bytes_written},
               {"bytes_per_cycle", ratio(bytes, cycles)},
               {"bus_utilisation", ratio(static_cast<double>(s.dram.bus_cycles), cycles)}};
  json bounds;
  for (const Bound& b : s.bounds) bounds[b.unit] = b.cycles;
  if (!s.bounds.empty()) {
    j["speed_of_light"] = {{"limiter", s.bounds.front().unit},
                           {"cycles", s.bounds.front().cycles},
                           {"efficiency", ratio(s.bounds.front().cycles, cycles)},
                           {"bounds", bounds}};
  }
  return j;
}

}  // namespace

void write_stats(const CycleStats& stats, const functional::ShaderStats& shader, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext != ".json" && ext != ".csv") {
    throw Error(fmt::format("statistics file '{}': the extension must be .json or .csv", path.string()));
  }
  const json j = stats_json(stats, shader);
  OutputFile file(path);
  std::ostream& out = file.stream();
  if (ext == ".json") {
    out << j.dump(2) << '\n';
  } else {
    // One row per value, named by its JSON pointer: /caches/node/hit_rate.
    out << "metric,value\n";
    const json flat = j.flatten();
    for (const auto& [key, value] : flat.items()) out << key << ',' << value.dump() << '\n';
  }
  file.commit();
}

std::string summarize(const CycleStats& s) {
  const auto cycles = static_cast<double>(s.cycles);
  std::uint64_t busy = 0, issues = 0, trace = 0, memory = 0, dependency = 0;
  for (const ShaderCoreTime& t : s.cores) {
    busy += t.busy;
    issues += t.chunk_issues;
    trace += t.wait_trace;
    memory += t.wait_memory;
    dependency += t.wait_dependency;
  }
  std::uint64_t tu_busy = 0, tu_mem = 0, tu_iu = 0, tests = 0;
  for (const TraversalUnitTime& t : s.tus) {
    tu_busy += t.busy;
    tu_mem += t.wait_memory;
    tu_iu += t.wait_iu;
    tests += t.tests;
  }
  const double core_cycles = cycles * static_cast<double>(s.cores.size());
  const double tu_cycles = cycles * static_cast<double>(s.tus.size());
  std::string text = fmt::format(
      "{} cycles on '{}' = {:.3f} ms at {} MHz ({:.2f} fps); simulated in {:.2f} s ({:.2f} M cycles/s)\n"
      "  shader cores: busy {:.1f}%, waiting for rays {:.1f}%, memory {:.1f}%, results {:.1f}%; IPC {:.2f} chunk "
      "instructions per core-cycle\n"
      "  traversal units: busy {:.1f}%, waiting for memory {:.1f}%, for the IU {:.1f}%; {} rays, {:.3f} IU tests/cycle\n"
      "  caches: node {:.1f}% hits, triangle {:.1f}%, data {:.1f}%; DRAM {:.2f} bytes/cycle ({:.1f}% of the bus)\n",
      s.cycles, s.config, s.frame_seconds() * 1e3, s.clock_mhz, ratio(1.0, s.frame_seconds()), s.host_seconds,
      ratio(cycles, s.host_seconds) / 1e6, 100 * ratio(static_cast<double>(busy), core_cycles),
      100 * ratio(static_cast<double>(trace), core_cycles), 100 * ratio(static_cast<double>(memory), core_cycles),
      100 * ratio(static_cast<double>(dependency), core_cycles), ratio(static_cast<double>(issues), core_cycles),
      100 * ratio(static_cast<double>(tu_busy), tu_cycles), 100 * ratio(static_cast<double>(tu_mem), tu_cycles),
      100 * ratio(static_cast<double>(tu_iu), tu_cycles), s.closest_rays + s.any_rays,
      ratio(static_cast<double>(tests), cycles), 100 * s.node_cache.hit_rate(), 100 * s.triangle_cache.hit_rate(),
      100 * s.data_cache.hit_rate(), ratio(static_cast<double>(s.dram.bytes_read + s.dram.bytes_written), cycles),
      100 * ratio(static_cast<double>(s.dram.bus_cycles), cycles));
  if (!s.bounds.empty()) {
    text += fmt::format("  speed of light: {:.0f} cycles, set by the {}; this frame reached {:.1f}% of it\n",
                        s.bounds.front().cycles, s.bounds.front().unit, 100 * ratio(s.bounds.front().cycles, cycles));
  }
  return text;
}

// The events go out as they come: the object's other members follow the array.
TimelineWriter::TimelineWriter(const std::filesystem::path& path) : file_(path) {
  file_.stream() << "{\"traceEvents\":[\n";
}

void TimelineWriter::add(const TimelineSlice& s) {
  std::ostream& out = file_.stream();
  auto it = std::find(tracks_.begin(), tracks_.end(), s.track);
  const auto tid = static_cast<int>(it - tracks_.begin());
  if (it == tracks_.end()) {
    tracks_.push_back(s.track);
    const json name = {{"name", "thread_name"}, {"ph", "M"}, {"pid", 0}, {"tid", tid}, {"args", {{"name", s.track}}}};
    out << (first_ ? "" : ",\n") << name.dump();
    first_ = false;
  }
  const json event = {{"name", s.name}, {"ph", "X"}, {"pid", 0}, {"tid", tid}, {"ts", s.begin}, {"dur", s.cycles}};
  out << (first_ ? "" : ",\n") << event.dump();
  first_ = false;
}

std::string timeline_cut_reason(const CycleStats& stats) {
  return fmt::format("cut at cycle {}: the timeline holds at most {} slices, which keeps the file small enough for "
                     "Perfetto to load; the later slices of the window are missing",
                     *stats.timeline_cut_at, stats.timeline_slices);
}

void TimelineWriter::finish(const CycleStats& stats) {
  json other = {{"config", stats.config}, {"time_unit", "1 us shown = 1 cycle"}, {"slices", stats.timeline_slices}};
  if (stats.timeline_cut_at) {
    other["cut_at_cycle"] = *stats.timeline_cut_at;
    other["cut_reason"] = timeline_cut_reason(stats);
  }
  file_.stream() << "\n],\"displayTimeUnit\":\"ns\",\"otherData\":" << other.dump() << "}\n";
  file_.commit();
}

}  // namespace rpu::cycle
