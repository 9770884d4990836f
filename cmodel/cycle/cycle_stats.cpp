#include "cycle/cycle_stats.hpp"

#include <algorithm>
#include <string_view>
#include <variant>

#include <fmt/format.h>

namespace rpu::cycle {

namespace {

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

void add_cache(StatsTree& t, const CacheStats& c) {
  t.set("accesses", c.accesses).set("hits", c.hits).set("merged", c.merged).set("misses", c.misses);
  t.set("writes", c.writes).set("write_backs", c.write_backs).set("hit_rate", c.hit_rate());
  t.set("mshr_wait_cycles", c.mshr_wait_cycles);
}

}  // namespace

void CycleStats::add_ray_caches(const CacheStats& node, const CacheStats& triangle) {
  node_cache += node;
  triangle_cache += triangle;
  node_port_lookups = std::max(node_port_lookups, node.accesses);
  triangle_port_lookups = std::max(triangle_port_lookups, triangle.accesses);
}

CycleStats& CycleStats::operator+=(const CycleStats& o) {
  const auto add_each = [](auto& to, const auto& from, auto add) {
    to.resize(std::max(to.size(), from.size()));
    for (std::size_t i = 0; i < from.size(); ++i) add(to[i], from[i]);
  };
  add_each(cores, o.cores, [](ShaderCoreTime& a, const ShaderCoreTime& b) {
    a.busy += b.busy;
    a.wait_trace += b.wait_trace;
    a.wait_memory += b.wait_memory;
    a.wait_dependency += b.wait_dependency;
    a.idle += b.idle;
    a.chunk_issues += b.chunk_issues;
    a.sfu_busy += b.sfu_busy;
  });
  add_each(tus, o.tus, [](TraversalUnitTime& a, const TraversalUnitTime& b) { a += b; });
  add_each(ius, o.ius, [](IntersectionUnitTime& a, const IntersectionUnitTime& b) {
    a.tests += b.tests;
    a.busy += b.busy;
  });
  add_each(pixel_cycles, o.pixel_cycles, [](std::uint32_t& a, std::uint32_t b) { a += b; });
  for (const Bound& b : o.bounds) {
    const auto same = std::find_if(bounds.begin(), bounds.end(), [&](const Bound& a) { return a.unit == b.unit; });
    if (same == bounds.end()) {
      bounds.push_back(b);
    } else {
      same->cycles += b.cycles;
    }
  }
  std::stable_sort(bounds.begin(), bounds.end(), [](const Bound& a, const Bound& b) { return a.cycles > b.cycles; });
  if (!timeline_cut_at && o.timeline_cut_at) timeline_cut_at = cycles + *o.timeline_cut_at;
  cycles += o.cycles;
  node_cache += o.node_cache;
  triangle_cache += o.triangle_cache;
  node_port_lookups += o.node_port_lookups;
  triangle_port_lookups += o.triangle_port_lookups;
  data_cache += o.data_cache;
  dram += o.dram;
  closest_rays += o.closest_rays;
  any_rays += o.any_rays;
  closest_latency += o.closest_latency;
  any_latency += o.any_latency;
  thread_instructions += o.thread_instructions;
  host_seconds += o.host_seconds;
  timeline_slices += o.timeline_slices;
  return *this;
}

StatsTree report(const CycleStats& s, const functional::ShaderStats& shader) {
  const auto cycles = static_cast<double>(s.cycles);
  StatsTree r;
  r.group("config").set("name", s.config);
  r.set("clock_mhz", s.clock_mhz).set("cycles", s.cycles);
  r.set("frame_seconds", s.frame_seconds()).set("fps", ratio(1.0, s.frame_seconds()));
  r.set("host_seconds", s.host_seconds).set("simulated_cycles_per_host_second", ratio(cycles, s.host_seconds));
  StatsTree& rays_group = r.group("rays");
  rays_group.set("closest", s.closest_rays).set("any", s.any_rays).set("total", s.closest_rays + s.any_rays);
  if (shader.self_hits_counted) rays_group.set("self_hits", shader.self_hits);
  const auto rays = static_cast<double>(s.closest_rays + s.any_rays);
  if (s.closest_latency.rays + s.any_latency.rays > 0) {
    StatsTree& latency = r.group("ray_latency");
    for (const auto& [name, l] : {std::pair{"closest", s.closest_latency}, std::pair{"any", s.any_latency}}) {
      const auto n = static_cast<double>(l.rays);
      latency.group(name)
          .set("rays", l.rays)
          .set("waiting", ratio(static_cast<double>(l.waiting), n))
          .set("in_unit", ratio(static_cast<double>(l.in_unit), n));
    }
  }
  r.group("rates")
      .set("rays_per_cycle", ratio(rays, cycles))
      .set("rays_per_second", ratio(rays, cycles) * s.clock_mhz * 1e6);  // at the modelled clock
  std::uint64_t issues = 0;
  for (const ShaderCoreTime& t : s.cores) issues += t.chunk_issues;
  StatsTree& instructions = r.group("instructions");
  instructions.set("thread", s.thread_instructions).set("chunk_issues", issues);
  instructions.set("ipc_per_core", ratio(static_cast<double>(issues), cycles * static_cast<double>(s.cores.size())));
  instructions.set("thread_ipc", ratio(static_cast<double>(s.thread_instructions), cycles));
  instructions.set("simd_efficiency",
                   ratio(static_cast<double>(s.thread_instructions), static_cast<double>(shader.lanes_issued)));
  StatsTree& by_class = instructions.group("by_class");
  for (std::size_t k = 0; k < spec::isa::kClassNames.size(); ++k) by_class.set(spec::isa::kClassNames[k], shader.retired[k]);
  StatsTree& cores = r.list("shader_cores");
  for (const ShaderCoreTime& t : s.cores) {
    cores.add()
        .set("busy", t.busy)
        .set("wait_trace", t.wait_trace)
        .set("wait_memory", t.wait_memory)
        .set("wait_dependency", t.wait_dependency)
        .set("idle", t.idle)
        .set("chunk_issues", t.chunk_issues)
        .set("utilisation", ratio(static_cast<double>(t.busy), cycles));
  }
  std::uint64_t steps = 0, tests = 0;
  StatsTree& tus = r.list("traversal_units");
  for (const TraversalUnitTime& t : s.tus) {
    steps += t.inner + t.leaves;
    StatsTree& tu = tus.add()
                        .set("busy", t.busy)
                        .set("wait_memory", t.wait_memory)
                        .set("wait_iu", t.wait_iu)
                        .set("idle", t.idle)
                        .set("rays", t.rays)
                        .set("inner_nodes", t.inner)
                        .set("leaves", t.leaves)
                        .set("prim_refs", t.refs)
                        .set("tests", t.tests);
    if (s.counts_pops) tu.set("pops", t.pops);
    // Slot-cycles: busy + wait_memory + wait_iu + idle = cycles x slots.
    tu.set("slots", std::uint64_t{s.tu_slots});
    tu.set("utilisation", ratio(static_cast<double>(t.busy), cycles * s.tu_slots));
  }
  r.set("tu_steps_per_cycle", ratio(static_cast<double>(steps), cycles));
  StatsTree& ius = r.list("intersection_units");
  for (const IntersectionUnitTime& t : s.ius) {
    tests += t.tests;
    ius.add().set("tests", t.tests).set("busy", t.busy).set("utilisation", ratio(static_cast<double>(t.busy), cycles));
  }
  r.set("iu_tests_per_cycle", ratio(static_cast<double>(tests), cycles));
  StatsTree& caches = r.group("caches");
  add_cache(caches.group("node"), s.node_cache);
  add_cache(caches.group("triangle"), s.triangle_cache);
  add_cache(caches.group("data"), s.data_cache);
  const double bytes = static_cast<double>(s.dram.bytes_read + s.dram.bytes_written);
  r.group("dram")
      .set("reads", s.dram.reads)
      .set("writes", s.dram.writes)
      .set("bytes_read", s.dram.bytes_read)
      .set("bytes_written", s.dram.bytes_written)
      .set("bytes_per_cycle", ratio(bytes, cycles))
      .set("bus_utilisation", ratio(static_cast<double>(s.dram.bus_cycles), cycles));
  if (!s.bounds.empty()) {
    StatsTree& light = r.group("speed_of_light");
    light.set("limiter", s.bounds.front().unit).set("cycles", s.bounds.front().cycles);
    light.set("efficiency", ratio(s.bounds.front().cycles, cycles));
    StatsTree& bounds = light.group("bounds");
    for (const Bound& b : s.bounds) bounds.set(b.unit, b.cycles);
  }
  return r;
}

std::string summarize(const StatsTree& r) {
  const double cycles = r.number("cycles");
  // A unit list's total of one counter, and that over the list's unit-cycles.
  const auto share = [&](std::string_view list, std::string_view counter) {
    double total = 0, unit_cycles = 0;
    for (const StatsTree& u : r.find(list)->children()) {
      total += u.number(counter);
      // A traversal unit's times count each of its ray slots' cycles.
      unit_cycles += cycles * (u.find("slots") ? u.number("slots") : 1.0);
    }
    return ratio(total, unit_cycles);
  };
  std::string text = fmt::format(
      "{} cycles on '{}' = {:.3f} ms at {} MHz ({:.2f} fps); simulated in {:.2f} s ({:.2f} M cycles/s)\n"
      "  shader cores: busy {:.1f}%, waiting for rays {:.1f}%, memory {:.1f}%, results {:.1f}%; IPC {:.2f} chunk "
      "instructions per core-cycle\n"
      "  traversal units: busy {:.1f}%, waiting for memory {:.1f}%, for the IU {:.1f}%; {} rays, {:.3f} IU tests/cycle\n"
      "  caches: node {:.1f}% hits, triangle {:.1f}%, data {:.1f}%; DRAM {:.2f} bytes/cycle ({:.1f}% of the bus)\n",
      std::get<std::uint64_t>(r.find("cycles")->value()), std::get<std::string>(r.find("config.name")->value()),
      r.number("frame_seconds") * 1e3, std::get<std::int64_t>(r.find("clock_mhz")->value()), r.number("fps"),
      r.number("host_seconds"), r.number("simulated_cycles_per_host_second") / 1e6,
      100 * share("shader_cores", "busy"), 100 * share("shader_cores", "wait_trace"),
      100 * share("shader_cores", "wait_memory"), 100 * share("shader_cores", "wait_dependency"),
      r.number("instructions.ipc_per_core"), 100 * share("traversal_units", "busy"),
      100 * share("traversal_units", "wait_memory"), 100 * share("traversal_units", "wait_iu"),
      std::get<std::uint64_t>(r.find("rays.total")->value()), r.number("iu_tests_per_cycle"),
      100 * r.number("caches.node.hit_rate"), 100 * r.number("caches.triangle.hit_rate"),
      100 * r.number("caches.data.hit_rate"), r.number("dram.bytes_per_cycle"), 100 * r.number("dram.bus_utilisation"));
  if (r.find("ray_latency")) {
    text += fmt::format(
        "  a ray's cycles: closest hit {:.0f} in a traversal unit after {:.0f} waiting for one, any hit {:.0f} after "
        "{:.0f}\n",
        r.number("ray_latency.closest.in_unit"), r.number("ray_latency.closest.waiting"),
        r.number("ray_latency.any.in_unit"), r.number("ray_latency.any.waiting"));
  }
  if (r.find("speed_of_light")) {
    text += fmt::format("  speed of light: {:.0f} cycles, set by the {}; this frame reached {:.1f}% of it\n",
                        r.number("speed_of_light.cycles"), std::get<std::string>(r.find("speed_of_light.limiter")->value()),
                        100 * r.number("speed_of_light.efficiency"));
  }
  return text;
}

}  // namespace rpu::cycle
