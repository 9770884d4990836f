// The cycle backend (docs/cycle-model.md): the same image as the functional backend,
// deterministic timing, and timing rules that can be checked by hand or by their
// direction (more bandwidth, more threads, warm caches).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "asm/assembler.hpp"
#include "asm/builtin_firmware.hpp"
#include "common/hardware_config.hpp"
#include "config/config.hpp"
#include "cycle/cycle_device.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "render/selection.hpp"
#include "scene/resolve.hpp"

namespace rpu::cycle {
namespace {

isa::Firmware assemble_text(const std::string& text) {
  return isa::assemble("test.s", [&](const std::filesystem::path&) { return std::optional<std::string>(text); });
}

RenderSettings settings(int width, int height, int spp = 1) {
  RenderSettings s;
  s.width = width;
  s.height = height;
  s.spp = spp;
  s.max_depth = 5;
  s.seed = 3;
  return s;
}

struct Frame {
  Image image;
  device::DeviceStats stats;
  CycleStats cycle;  // render_cycle only
};

Frame render(device::Device& dev, const Scene& scene, const MemoryImage& image, const isa::Firmware& firmware,
             const RenderSettings& s) {
  Frame f;
  f.image = device::render_frame(dev, scene, image, firmware, s);
  f.stats = dev.stats();
  return f;
}

Frame render_cycle(const spec::HardwareConfig& config, const Scene& scene, const MemoryImage& image,
                   const isa::Firmware& firmware, const RenderSettings& s) {
  CycleStats cycle;
  CycleOptions options;
  options.frame_stats = [&cycle](const CycleStats& st) { cycle = st; };
  const auto dev = make_cycle_device(config, fp::format_by_name(config.format), options);
  Frame f = render(*dev, scene, image, firmware, s);
  f.cycle = std::move(cycle);
  return f;
}

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

using SceneAndConfig = std::tuple<std::string, std::string>;
class CycleImage : public testing::TestWithParam<SceneAndConfig> {};

// Issue 5: the cycle backend's image is the functional backend's, bit for bit, for every
// test scene and configuration (each in its own number format).
TEST_P(CycleImage, IsBitIdenticalToTheFunctionalImage) {
  const auto& [scene_name, config_name] = GetParam();
  const Scene scene = resolve_scene(scene_name);
  const spec::HardwareConfig& config = hardware_config(config_name);
  const functional::SceneImage si =
      functional::make_scene_image(scene, kd_build_config_for(std::string(config.name)), IsectMode::kWoop);
  const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
  const RenderSettings s = settings(24, 18);
  const auto functional = device::make_functional_device(config, fp::format_by_name(config.format));
  const Frame expected = render(*functional, scene, si.image, firmware, s);
  const Frame actual = render_cycle(config, scene, si.image, firmware, s);
  EXPECT_TRUE(same_bits(expected.image, actual.image)) << scene_name << " on " << config_name;
  EXPECT_GT(actual.cycle.cycles, 0u);
  // The device's report is the typed statistics as a tree.
  EXPECT_EQ(actual.stats.report.number("cycles"), static_cast<double>(actual.cycle.cycles));
  EXPECT_EQ(actual.stats.report.number("rays.total"), static_cast<double>(actual.stats.shader.closest_rays +
                                                                          actual.stats.shader.any_rays));
  EXPECT_EQ(expected.stats.report.number("instructions.thread"), actual.stats.report.number("instructions.thread"));
  // Both ran the same instructions; the cycle model adds when, not what.
  EXPECT_EQ(expected.stats.shader.instructions(), actual.stats.shader.instructions());
  EXPECT_EQ(expected.stats.shader.tests, actual.stats.shader.tests);
  std::uint64_t tests = 0;
  for (const IntersectionUnitTime& iu : actual.cycle.ius) tests += iu.tests;
  EXPECT_EQ(tests, actual.stats.shader.tests);
}

INSTANTIATE_TEST_SUITE_P(ScenesAndConfigs, CycleImage,
                         testing::Combine(testing::Values("cornell", "balls:2", "scenes/bunny.json"),
                                          testing::Values("tiny", "default", "rpu2005", "drpu")),
                         [](const testing::TestParamInfo<SceneAndConfig>& i) {
                           std::string name = std::get<0>(i.param) + "_" + std::get<1>(i.param);
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// The watertight records and the IU's other latency change the timing, not the image.
TEST(CycleModel, WatertightImageIsTheFunctionalImage) {
  const Scene scene = resolve_scene("balls:1");
  const spec::HardwareConfig& config = hardware_config("default");
  const functional::SceneImage si =
      functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWatertight);
  const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
  const auto functional = device::make_functional_device(config, fp::kFp32);
  const Frame expected = render(*functional, scene, si.image, firmware, settings(20, 16));
  const Frame actual = render_cycle(config, scene, si.image, firmware, settings(20, 16));
  EXPECT_TRUE(same_bits(expected.image, actual.image));
}

// A selected frame (docs/selection.md) is two launches: the same image and work as the
// functional backend's, and the frame's statistics are both launches' together.
TEST(CycleModel, SelectedFrameIsTheFunctionalFrame) {
  const Scene scene = resolve_scene("cornell");
  const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
  for (const char* name : {"default", "rpu2005"}) {
    const spec::HardwareConfig& config = hardware_config(name);
    const functional::SceneImage si =
        functional::make_scene_image(scene, kd_build_config_for(name), IsectMode::kWoop);
    RenderSettings s = settings(23, 17);
    s.select = parse_selection("3:0.05");
    const auto functional = device::make_functional_device(config, fp::format_by_name(config.format));
    const Frame expected = render(*functional, scene, si.image, firmware, s);
    const Frame actual = render_cycle(config, scene, si.image, firmware, s);
    EXPECT_TRUE(same_bits(expected.image, actual.image)) << name;
    EXPECT_EQ(expected.stats.shader.instructions(), actual.stats.shader.instructions()) << name;
    EXPECT_EQ(expected.stats.shader.closest_rays, actual.stats.shader.closest_rays) << name;
    EXPECT_EQ(expected.stats.shader.tests, actual.stats.shader.tests) << name;
    const CycleStats& st = actual.cycle;
    EXPECT_EQ(st.closest_rays + st.any_rays, actual.stats.shader.closest_rays + actual.stats.shader.any_rays);
    EXPECT_EQ(actual.stats.report.number("cycles"), static_cast<double>(st.cycles));
    for (const ShaderCoreTime& t : st.cores) {
      EXPECT_EQ(t.busy + t.wait_trace + t.wait_memory + t.wait_dependency + t.idle, st.cycles) << name;
    }
    std::uint64_t pixel_cycles = 0;
    for (const auto c : st.pixel_cycles) pixel_cycles += c;
    EXPECT_GT(pixel_cycles, 0u);
  }
}

struct Cornell {
  Scene scene = resolve_scene("cornell");
  functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for("tiny"), IsectMode::kWoop);
  isa::Firmware firmware = isa::builtin_firmware("whitted.s");
};

TEST(CycleModel, SameInputsGiveTheSameCycles) {
  const Cornell c;
  const Frame a = render_cycle(hardware_config("default"), c.scene, c.si.image, c.firmware, settings(16, 12));
  const Frame b = render_cycle(hardware_config("default"), c.scene, c.si.image, c.firmware, settings(16, 12));
  EXPECT_EQ(a.cycle.cycles, b.cycle.cycles);
  EXPECT_EQ(a.cycle.pixel_cycles, b.cycle.pixel_cycles);
  EXPECT_EQ(a.cycle.dram.bytes_read, b.cycle.dram.bytes_read);
}

// Every cycle of every unit is busy, waiting or idle, exactly once.
TEST(CycleModel, UnitTimeAddsUpToTheFrame) {
  const Cornell c;
  const Frame f = render_cycle(hardware_config("default"), c.scene, c.si.image, c.firmware, settings(16, 12));
  const CycleStats& st = f.cycle;
  std::uint64_t busy = 0;
  for (const ShaderCoreTime& t : st.cores) {
    EXPECT_EQ(t.busy + t.wait_trace + t.wait_memory + t.wait_dependency + t.idle, st.cycles);
    EXPECT_GE(t.busy, t.chunk_issues);
    busy += t.busy;
  }
  // At most issue_lanes lanes of a chunk instruction enter a core's pipeline a cycle.
  EXPECT_GE(busy * static_cast<std::uint64_t>(hardware_config("default").issue_lanes), st.thread_instructions);
  // A unit's times are slot-cycles.
  for (const TraversalUnitTime& t : st.tus) {
    EXPECT_EQ(t.busy + t.wait_memory + t.wait_iu + t.idle, st.cycles * std::uint64_t{st.tu_slots});
  }
  EXPECT_EQ(st.closest_rays + st.any_rays, f.stats.shader.closest_rays + f.stats.shader.any_rays);
  // Every ray's latency is counted once, in its mode.
  EXPECT_EQ(st.closest_latency.rays, st.closest_rays);
  EXPECT_EQ(st.any_latency.rays, st.any_rays);
  ASSERT_FALSE(st.bounds.empty());
  EXPECT_LE(st.bounds.front().cycles, static_cast<double>(st.cycles));  // nothing beats the speed of light
}

// A traversal unit tests on its own share of the IUs, as rpu_ray_unit pairs a TU with its
// IU: four TUs on four IUs one each, on eight two each, on two IUs two TUs share one.
TEST(CycleModel, EachTraversalUnitTestsOnItsOwnIntersectionUnits) {
  const Cornell c;
  for (const int ius : {4, 8, 2}) {
    spec::HardwareConfig config = hardware_config("default");
    config.intersection_units = ius;
    const Frame f = render_cycle(config, c.scene, c.si.image, c.firmware, settings(16, 12));
    const CycleStats& st = f.cycle;
    ASSERT_EQ(st.tus.size(), 4u);
    ASSERT_EQ(st.ius.size(), static_cast<std::size_t>(ius));
    for (std::size_t i = 0; i < st.ius.size(); ++i) {
      std::uint64_t tests = 0;  // of the TUs whose share holds IU i
      for (std::size_t u = 0; u < 4; ++u) {
        if (ius >= 4 ? i * 4 / static_cast<std::size_t>(ius) == u : u * static_cast<std::size_t>(ius) / 4 == i) {
          tests += st.tus[u].tests;
        }
      }
      if (ius >= 4) {
        // Its TU's tests are split over its IUs; each pair adds up to the TU's.
        const std::size_t per = static_cast<std::size_t>(ius) / 4, first = i / per * per;
        std::uint64_t share = 0;
        for (std::size_t k = first; k < first + per; ++k) share += st.ius[k].tests;
        EXPECT_EQ(share, tests) << ius << " IUs, IU " << i;
      } else {
        EXPECT_EQ(st.ius[i].tests, tests) << ius << " IUs, IU " << i;
      }
      EXPECT_GT(st.ius[i].tests, 0u) << ius << " IUs, IU " << i;
    }
  }
}

// With ray slots a unit's times are slot-cycles: they add up to cycles x slots, and the
// slots of one unit walk rays side by side, so a frame bound by one traversal unit
// (rpu2005's) takes fewer cycles with more of them and the same work.
TEST(CycleModel, RaySlotsShareTheFrameAndSpeedUpATraversalBoundOne) {
  const Cornell c;
  spec::HardwareConfig config = hardware_config("rpu2005");
  config.tu_pipe = 0;  // walkers, which take their lines in order
  config.tu_by_tag = 0;
  const functional::SceneImage si =
      functional::make_scene_image(c.scene, kd_build_config_for("rpu2005"), IsectMode::kWoop);
  std::uint64_t previous = std::numeric_limits<std::uint64_t>::max(), tests = 0;
  for (int slots : {1, 2, 4, 8}) {
    config.tu_slots = slots;
    const Frame f = render_cycle(config, c.scene, si.image, c.firmware, settings(32, 24));
    const CycleStats& st = f.cycle;
    EXPECT_EQ(st.tu_slots, static_cast<std::uint32_t>(slots));
    for (const TraversalUnitTime& t : st.tus) {
      EXPECT_EQ(t.busy + t.wait_memory + t.wait_iu + t.idle, st.cycles * static_cast<std::uint64_t>(slots)) << slots;
    }
    EXPECT_LT(st.cycles, previous) << slots << " slots";
    previous = st.cycles;
    if (tests == 0) tests = f.stats.shader.tests;
    EXPECT_EQ(f.stats.shader.tests, tests) << slots << " slots";
  }
}

// A pipelined unit (tu_pipe = 1, rpu_tu_pipe) walks the same rays as its walkers would:
// the same image and work; its slot-cycles add up to cycles x slots; and on a frame bound
// by the one traversal unit (rpu2005's with four shader cores) its shared pipeline takes
// fewer cycles than as many walker slots, and more slots never make a ray take longer
// (the frame's cycles may: which core's pixels finish last moves with the timing).
TEST(CycleModel, APipelinedUnitWalksTheSameRaysFasterThanItsWalkers) {
  const Cornell c;
  spec::HardwareConfig config = hardware_config("rpu2005");
  config.shader_cores = 4;
  const functional::SceneImage si =
      functional::make_scene_image(c.scene, kd_build_config_for("rpu2005"), IsectMode::kWoop);
  config.tu_pipe = 0;
  config.tu_by_tag = 0;
  config.tu_slots = 8;
  const Frame walkers = render_cycle(config, c.scene, si.image, c.firmware, settings(32, 24));
  config.tu_pipe = 1;
  config.tu_by_tag = hardware_config("rpu2005").tu_by_tag;
  double previous = std::numeric_limits<double>::max();
  for (int slots : {2, 8, 16}) {
    config.tu_slots = slots;
    const Frame f = render_cycle(config, c.scene, si.image, c.firmware, settings(32, 24));
    const CycleStats& st = f.cycle;
    RayLatency rays = st.closest_latency;
    rays += st.any_latency;
    const double per_ray = static_cast<double>(rays.waiting + rays.in_unit) / static_cast<double>(rays.rays);
    EXPECT_TRUE(same_bits(walkers.image, f.image)) << slots;
    EXPECT_EQ(f.stats.shader.tests, walkers.stats.shader.tests) << slots;
    ASSERT_EQ(st.tus.size(), 1u);
    const TraversalUnitTime& t = st.tus[0];
    EXPECT_EQ(t.busy + t.wait_memory + t.wait_iu + t.idle, st.cycles * static_cast<std::uint64_t>(slots)) << slots;
    EXPECT_EQ(t.tests, f.stats.shader.tests) << slots;
    EXPECT_EQ(t.rays, st.closest_rays + st.any_rays) << slots;
    EXPECT_LE(per_ray, previous) << slots << " slots: a ray's cycles at the dispatch and in the unit";
    previous = per_ray;
    if (slots == 8) {
      EXPECT_LT(st.cycles, walkers.cycle.cycles) << "8 slots: the pipeline against 8 walkers";
    }
  }
}

// More DRAM bandwidth buys cycles on a fixed frame: the widest bus is faster than the
// narrowest, and no doubling costs more than 2%. Not none: threads that meet their data
// sooner can interleave worse on the other units (a scheduling anomaly, as in Graham's
// list scheduling), so one doubling on tiny's Cornell box costs 0.9%.
TEST(CycleModel, MoreDramBandwidthBuysCycles) {
  const Cornell c;
  spec::HardwareConfig config = hardware_config("tiny");
  std::vector<std::uint64_t> cycles;
  for (int bytes = 1; bytes <= 64; bytes *= 2) {
    config.dram.bytes_per_cycle = bytes;
    cycles.push_back(render_cycle(config, c.scene, c.si.image, c.firmware, settings(16, 12)).cycle.cycles);
    if (cycles.size() > 1) {
      EXPECT_LE(static_cast<double>(cycles.back()), 1.02 * static_cast<double>(cycles[cycles.size() - 2]))
          << bytes << " bytes/cycle against half as many";
    }
  }
  EXPECT_LT(1.1 * static_cast<double>(cycles.back()), static_cast<double>(cycles.front()))
      << "64 bytes/cycle against 1";
}

// Configurations changed at run time (rpu::config, --set) move a frame the way the
// hardware would: more shader cores never cost cycles when the shaders bound the frame.
TEST(CycleModel, MoreShaderCoresNeverCostCyclesOnAShaderBoundFrame) {
  // Arithmetic only, a chain of dependent mads: no rays and no loads, so only the cores
  // bound the frame.
  std::string text = "raygen:\n        lif     r1, 1.0\n        lif     r2, 0.5\n";
  for (int i = 0; i < 64; ++i) text += "        mad     r2, r2, r1, r1\n";
  text += "        halt\nhit_whitted:\n        ret\n";
  const isa::Firmware firmware = assemble_text(text);
  const Cornell c;
  std::uint64_t previous = std::numeric_limits<std::uint64_t>::max(), one_core = 0;
  for (int cores = 1; cores <= 32; cores *= 2) {
    const spec::HardwareConfig config = config::resolve("tiny", {fmt::format("shader_cores={}", cores)});
    const Frame f = render_cycle(config, c.scene, c.si.image, firmware, settings(16, 16));
    const CycleStats& st = f.cycle;
    for (const ShaderCoreTime& core : st.cores) {
      EXPECT_EQ(core.wait_trace + core.wait_memory, 0u) << cores << " cores: the frame is not shader-bound";
    }
    EXPECT_LE(st.cycles, previous) << cores << " shader cores";
    if (cores == 1) one_core = st.cycles;
    previous = st.cycles;
  }
  // 256 pixels on 4 threads a core: 32 cores run them in an eighth of 1 core's rounds.
  EXPECT_LT(previous * 4, one_core) << "1 core: " << one_core << " cycles, 32 cores: " << previous;
}

// A larger node cache never lowers its hit rate on a fixed frame: more sets of the same
// ways hold every line the smaller one held (LRU inclusion). One node cache for all
// units (ray_caches = 1): with a pair per two units, which unit and so which cache a ray
// reaches depends on the timing that the size changes.
TEST(CycleModel, ALargerNodeCacheNeverLowersItsHitRate) {
  const Scene scene = resolve_scene("scenes/bunny.json");
  const functional::SceneImage si =
      functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWoop);
  const isa::Firmware firmware = isa::builtin_firmware("whitted.s");
  double previous = -1, smallest = 0;
  for (int bytes = 1024; bytes <= 131072; bytes *= 2) {
    const spec::HardwareConfig config = config::resolve("default", {fmt::format("node_cache.bytes={}", bytes), "ray_caches=1"});
    const Frame f = render_cycle(config, scene, si.image, firmware, settings(24, 18));
    const double rate = f.cycle.node_cache.hit_rate();
    EXPECT_GE(rate, previous) << bytes << "-byte node cache";
    if (previous < 0) smallest = rate;
    previous = rate;
  }
  EXPECT_GT(previous, smallest + 0.05) << "the sizes should matter on this frame";
}

// On a frame bound by DRAM latency, twice the threads hide much of it.
TEST(CycleModel, DoublingThreadsHidesLatencyOnAMemoryBoundFrame) {
  const Cornell c;
  spec::HardwareConfig config = hardware_config("tiny");
  config.dram.latency = 400;
  config.traversal_units = 16;
  config.intersection_units = 4;
  config.threads_per_core = 4;
  const Frame few = render_cycle(config, c.scene, c.si.image, c.firmware, settings(16, 16));
  config.threads_per_core = 8;
  const Frame more = render_cycle(config, c.scene, c.si.image, c.firmware, settings(16, 16));
  EXPECT_TRUE(same_bits(few.image, more.image));
  const auto f = static_cast<double>(few.cycle.cycles), m = static_cast<double>(more.cycle.cycles);
  EXPECT_LT(m, 0.7 * f) << "4 threads: " << f << " cycles, 8 threads: " << m;
}

// One thread, one pixel, a ray straight at the one-triangle scene: its tree is a leaf
// holding the triangle, so the walk is leaf fetch, prim-ref read, record read and one
// IU test. The first ray finds every cache cold, the second (the same ray) warm.
struct OneRay {
  Scene scene = resolve_scene("tests/isa/scenes/one_triangle.json");
  functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for("tiny"), IsectMode::kWoop);
  spec::HardwareConfig config = [] {
    spec::HardwareConfig c = hardware_config("tiny");
    c.threads_per_core = 1;
    c.chunk_size = 1;
    return c;
  }();

  static std::string program(int traces) {
    std::string text = R"(
raygen:
        lif     r1.xy, 0.0
        lif     r1.z, 5.0
        lif     r1.w, 0.0
        lif     r2.xy, 0.0
        lif     r2.z, -1.0
        lif     r2.w, inf
)";
    for (int i = 0; i < traces; ++i) text += fmt::format("        trace   r{}, r1, r2\n", 3 + i);
    return text + "        halt\nhit_whitted:\n        ret\n";
  }
  CycleStats stats(int traces) const {
    return render_cycle(config, scene, si.image, assemble_text(program(traces)), settings(1, 1)).cycle;
  }
  std::uint64_t cycles(int traces) const { return stats(traces).cycles; }
  // The cycles of a read that misses: tag check, DRAM latency, one line on the bus, the
  // chip's path to the DRAM.
  Cycle miss(const spec::CacheConfig& cache) const {
    return static_cast<Cycle>(cache.hit_latency + config.dram.latency + config.latency.line_wait +
                              (cache.line_bytes + config.dram.bytes_per_cycle - 1) / config.dram.bytes_per_cycle);
  }
  std::uint32_t line(std::uint32_t address, const spec::CacheConfig& cache) const {
    return address / static_cast<std::uint32_t>(cache.line_bytes);
  }
};

TEST(CycleModel, OneRaysCyclesEqualTheHandCount) {
  const OneRay r;
  const spec::HardwareConfig& c = r.config;
  const std::uint32_t ref = r.si.layout.prim_refs.offset;
  const std::uint32_t record = r.si.layout.isect_records.offset;
  const std::uint32_t record_end = record + spec::memory::kTriangleRecordWoopBytes - 1;
  // The layout this count assumes: the ref and the record in lines of their own, the
  // record in one line (the image puts sections on 64-byte boundaries).
  ASSERT_NE(r.line(ref, c.triangle_cache), r.line(record, c.triangle_cache));
  ASSERT_EQ(r.line(record, c.triangle_cache), r.line(record_end, c.triangle_cache));

  // The six lif write r1 and r2 in three parts each: a write waits for the one before
  // it to the same register (issue, its lane's S0 a cycle later, then `result`); r2's
  // first waits for the chunk's reissue after r1's last. The trace waits for r2.
  const auto result = static_cast<Cycle>(c.latency.result), reissue = static_cast<Cycle>(c.latency.reissue);
  const Cycle issue = 2 * (1 + result) + 1 + reissue + 3 * (1 + result);
  // The ray reaches the traversal unit to_unit after its lane's S0; every memory answer
  // takes memory_wait more than the cache, the IU's iu_wait more than its latency; the
  // 48-byte record is three pieces on the cache port, one a cycle.
  const Cycle arrive = issue + 1 + static_cast<Cycle>(c.latency.to_unit);
  const Cycle mw = static_cast<Cycle>(c.tu.memory_wait);
  const Cycle pieces = port_pieces(record, spec::memory::kTriangleRecordWoopBytes);
  ASSERT_EQ(pieces, 3u);
  const Cycle setup = static_cast<Cycle>(c.tu.setup_woop);
  const Cycle test = static_cast<Cycle>(c.iu.woop + c.tu.iu_wait);
  // The record's later pieces wait for its line, and are answered one a cycle after it.
  const Cycle cold = setup + (r.miss(c.node_cache) + mw + static_cast<Cycle>(c.tu.leaf)) +
                     (r.miss(c.triangle_cache) + mw) + (r.miss(c.triangle_cache) + (pieces - 1) + mw + test);
  const Cycle warm = setup + static_cast<Cycle>(c.node_cache.hit_latency + c.tu.leaf) + mw +
                     static_cast<Cycle>(c.triangle_cache.hit_latency) + mw +
                     static_cast<Cycle>(c.triangle_cache.hit_latency) + (pieces - 1) + mw + test;
  // The halt does not wait for the ray; the frame ends the cycle after the ray's last step.
  EXPECT_EQ(r.cycles(1), arrive + cold + 1);
  // The second, identical ray waits for the one traversal unit (and its turnaround) and
  // then hits in every cache: all-miss costs three line fills more than all-hit, nothing
  // else.
  EXPECT_EQ(r.cycles(2), arrive + cold + static_cast<Cycle>(c.tu.turnaround) + warm + 1);
  EXPECT_EQ(cold - warm, r.miss(c.node_cache) - static_cast<Cycle>(c.node_cache.hit_latency) +
                             2 * (r.miss(c.triangle_cache) - static_cast<Cycle>(c.triangle_cache.hit_latency)));
}

// A ray's latency splits into waiting for a unit and its time in one: the first ray finds
// the unit free and spends its cold walk there; the second waits for the first, then
// spends its warm walk.
TEST(CycleModel, ARaysLatencyIsItsWaitAndItsWalk) {
  const OneRay r;
  const CycleStats one = r.stats(1);
  ASSERT_EQ(one.closest_latency.rays, 1u);
  EXPECT_EQ(one.any_latency.rays, 0u);
  EXPECT_EQ(one.closest_latency.waiting, 0u);
  const Cycle cold = one.closest_latency.in_unit;
  const CycleStats two = r.stats(2);
  ASSERT_EQ(two.closest_latency.rays, 2u);
  const Cycle warm = two.closest_latency.in_unit - cold;
  EXPECT_LT(warm, cold);
  // The second trace issues `reissue` cycles after the first's lane entered S0, so its
  // ray arrives 1 + reissue cycles after the first, and is taken after the first's walk
  // and the unit's turnaround.
  const auto later = static_cast<Cycle>(1 + r.config.latency.reissue);
  EXPECT_EQ(two.closest_latency.waiting, cold + static_cast<Cycle>(r.config.tu.turnaround) - later);
  // The frame ends the cycle after the second ray's answer.
  EXPECT_EQ(two.cycles, one.cycles + static_cast<Cycle>(r.config.tu.turnaround) + warm);
}

TEST(CycleModel, AShaderFaultIsReportedAsByTheFunctionalBackend) {
  const OneRay r;
  const isa::Firmware firmware = assemble_text("raygen:\n        ld r1, [r0 + 0x7ffffff0]\n        halt\nhit_whitted:\n        ret\n");
  const auto functional = device::make_functional_device(r.config, fp::kFp32);
  const auto cycle = make_cycle_device(r.config, fp::kFp32);
  std::string expected, actual;
  try {
    render(*functional, r.scene, r.si.image, firmware, settings(2, 2));
  } catch (const Error& e) {
    expected = e.what();
  }
  try {
    render(*cycle, r.scene, r.si.image, firmware, settings(2, 2));
  } catch (const Error& e) {
    actual = e.what();
  }
  EXPECT_NE(expected.find("shader fault"), std::string::npos) << expected;
  EXPECT_EQ(actual, expected);
}

// The fault of a frame on every backend: functional on one and on several host
// threads, and cycle.
std::vector<std::string> faults_on_every_backend(const isa::Firmware& firmware, std::uint64_t watchdog,
                                                 int width, int height) {
  const Scene scene = resolve_scene("tests/isa/scenes/one_triangle.json");
  const spec::HardwareConfig& config = hardware_config("default");
  const functional::SceneImage si =
      functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWoop);
  std::vector<std::unique_ptr<device::Device>> devices;
  for (const int threads : {1, 3}) {
    device::FunctionalOptions o;
    o.host_threads = threads;
    o.watchdog = watchdog;
    devices.push_back(device::make_functional_device(config, fp::kFp32, o));
  }
  CycleOptions o;
  o.watchdog = watchdog;
  devices.push_back(make_cycle_device(config, fp::kFp32, o));
  std::vector<std::string> faults;
  for (const auto& dev : devices) {
    try {
      render(*dev, scene, si.image, firmware, settings(width, height));
      faults.push_back("no fault");
    } catch (const Error& e) {
      faults.push_back(e.what());
    }
  }
  return faults;
}

// Issue 14 (7): pixel 0 halts, even pixels fault at pc 5 and odd ones one step later at
// pc 6 (the smallest pc issues first). Pixel 2 faults first in time, pixel 1 first in
// pixel order: every backend names pixel 1.
TEST(CycleModel, TheFirstFaultInPixelOrderIsReportedByEveryBackend) {
  const isa::Firmware firmware = assemble_text(R"(
raygen:
        rdsr    r0, pixel
        li      r2.x, 0x30000000
        bz      r0.z, done
        andi    r1.x, r0.z, 1
        bnz     r1.x, odd
        ld      r3, [r2]
odd:
        ld      r3, [r2 + 16]
done:
        halt
hit_whitted:
        ret
)");
  for (const std::string& fault : faults_on_every_backend(firmware, 100'000, 16, 16)) {
    EXPECT_EQ(fault,
              "shader fault in thread 1 (core 0, chunk 0, lane 1; pixel 1, 0) at pc 6 (ld r3, [r2 + 16]): load of 16 "
              "bytes at address 0x30000010 is outside the device memory (test.s:10; code label odd)");
  }
}

// Pixel 37 runs away in `loop` (at code label spin); pixel 50 faults at once, long
// before 37's runaway is stopped. A runaway is counted per thread and pixel on every
// backend, and pixel 37 is the one reported.
isa::Firmware runaway_at_pixel_37(std::string_view loop) {
  return assemble_text(fmt::format(R"(
raygen:
        rdsr    r0, pixel
        iaddi   r1.x, r0.z, -50
        bz      r1.x, bad_load
        iaddi   r1.x, r0.z, -37
        bnz     r1.x, done
spin:
{}
bad_load:
        li      r2.x, 0x30000000
        ld      r3, [r2]
done:
        halt
hit_whitted:
        ret
)",
                                   loop));
}

// A loop that writes runs to the watchdog.
TEST(CycleModel, ARunawayPixelIsReportedBeforeALaterPixelsEarlierFault) {
  const isa::Firmware firmware = runaway_at_pixel_37("        iaddi   r4.x, r4.x, 1\n        bra     spin");
  for (const std::string& fault : faults_on_every_backend(firmware, 5'000, 8, 8)) {
    EXPECT_EQ(fault,
              "shader fault in thread 41 (core 1, chunk 2, lane 1; pixel 5, 4) at pc 6 (bra 5): watchdog: the thread "
              "retired 5000 instructions for one pixel; a runaway shader? (test.s:10; code label spin + 1)");
  }
}

// A loop that writes nothing is stopped after as many branches in a row as the code
// has instructions (10 here), at the default watchdog of 5 x 10^7 too.
TEST(CycleModel, ASpinningPixelIsStoppedAtOnceOnEveryBackend) {
  const isa::Firmware firmware = runaway_at_pixel_37("        bra     spin");
  for (const std::string& fault : faults_on_every_backend(firmware, 50'000'000, 8, 8)) {
    EXPECT_EQ(fault,
              "shader fault in thread 41 (core 1, chunk 2, lane 1; pixel 5, 4) at pc 5 (bra 5): spin: the thread "
              "loops without writing anything (10 branches in a row that wrote only the pc, as many as the code has "
              "instructions), so it can never end; a runaway shader (test.s:9; code label spin)");
  }
}

// Issue 14 class 8: the timeline reaches its sink slice by slice during the frame; at
// its most it is cut, and both the statistics and the file's metadata say where.
TEST(CycleTimeline, StreamsEverySliceAndSaysWhereItWasCut) {
  const Cornell c;
  const spec::HardwareConfig& config = hardware_config("tiny");
  // Progress reports before the first slice arrived, and in all: streamed slices
  // arrive before the frame ends, not all at once after it.
  std::size_t reports = 0, reports_before_first_slice = 0;
  const auto frame = [&](std::uint64_t max_slices, std::vector<TimelineSlice>& slices) {
    CycleOptions options;
    options.timeline_begin = 0;
    options.timeline_end = 5000;
    options.timeline_max_slices = max_slices;
    options.timeline = [&](const TimelineSlice& s) {
      if (slices.empty()) reports_before_first_slice = reports;
      slices.push_back(s);
    };
    CycleStats stats;
    options.frame_stats = [&stats](const CycleStats& st) { stats = st; };
    const auto dev = make_cycle_device(config, fp::format_by_name(config.format), options);
    reports = 0;
    device::render_frame(*dev, c.scene, c.si.image, c.firmware, settings(16, 12),
                         [&](std::size_t, std::size_t) { ++reports; });
    return stats;
  };
  std::vector<TimelineSlice> all, cut;
  const CycleStats whole = frame(1'000'000, all);
  EXPECT_GT(reports, 1u);
  EXPECT_EQ(reports_before_first_slice, 0u);
  EXPECT_GT(all.size(), 500u);
  EXPECT_EQ(whole.timeline_slices, all.size());
  EXPECT_FALSE(whole.timeline_cut_at);
  const CycleStats part = frame(500, cut);
  ASSERT_EQ(cut.size(), 500u);
  EXPECT_EQ(part.timeline_slices, 500u);
  // The first slice left out is the 501st the whole timeline received.
  ASSERT_TRUE(part.timeline_cut_at);
  EXPECT_EQ(*part.timeline_cut_at, all[500].begin);
  for (std::size_t i = 0; i + 8 < cut.size(); ++i) {
    EXPECT_EQ(cut[i].track + cut[i].name, all[i].track + all[i].name) << i;
    EXPECT_EQ(cut[i].begin, all[i].begin) << i;
  }

  const std::filesystem::path file = std::filesystem::path(testing::TempDir()) / "cut_timeline.json";
  {
    TimelineWriter writer(file);
    for (const TimelineSlice& s : cut) writer.add(s);
    writer.finish(part);
  }
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json& other = j.at("otherData");
  EXPECT_EQ(other.at("cut_at_cycle").get<Cycle>(), *part.timeline_cut_at);
  EXPECT_EQ(other.at("slices").get<std::uint64_t>(), 500u);
  EXPECT_EQ(other.at("cut_reason").get<std::string>(), timeline_cut_reason(part));
  EXPECT_EQ(timeline_cut_reason(part),
            fmt::format("cut at cycle {}: the timeline holds at most 500 slices, which keeps the file small enough "
                        "for Perfetto to load; the later slices of the window are missing",
                        *part.timeline_cut_at));
  const auto slices = std::count_if(j.at("traceEvents").begin(), j.at("traceEvents").end(),
                                    [](const nlohmann::json& e) { return e.at("ph") == "X"; });
  EXPECT_EQ(slices, 500);
}

}  // namespace
}  // namespace rpu::cycle
