// A shader core's timing alone (cycle/core_timing.hpp): one core of the named `tiny`
// configuration driven through its links to the chip, its issue schedule against one
// counted by hand from the pipeline's rules (docs/cycle-model.md "Shader cores"), with
// one lane a cycle and with two.
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "asm/assembler.hpp"
#include "common/hardware_config.hpp"
#include "cycle/core_timing.hpp"
#include "functional/scene_image.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu::cycle {
namespace {

// The chip around one core: a frame of one round of pixels, pixel p on thread p, as
// DeviceBase::lanes_of gives them; no rays, no faults.
class OneCoreChip final : public CoreTiming::Chip {
 public:
  explicit OneCoreChip(int chunk_size) : chunk_size_(static_cast<std::uint32_t>(chunk_size)) {}

  void queue_ray(Ray, Cycle) override { ADD_FAILURE() << "the program traces no ray"; }
  std::size_t queued_rays(std::uint32_t) const override { return 0; }
  void round_lanes(std::uint64_t round, std::uint64_t chunk,
                   std::vector<functional::ShaderCore::Lane>& lanes) const override {
    lanes.clear();
    if (round > 0) return;
    for (std::uint32_t l = 0; l < chunk_size_; ++l) {
      const auto thread = static_cast<std::uint32_t>(chunk) * chunk_size_ + l;
      lanes.push_back({thread, 0, static_cast<std::uint32_t>(chunk), l, thread});
    }
  }
  void round_done() override { ++rounds; }
  std::uint32_t first_fault() const override { return CoreTiming::kNoFault; }
  void fault(std::uint32_t) override { ADD_FAILURE() << "the program does not fault"; }
  void halted(std::uint32_t pixel, Cycle cycles) override { halts[pixel] = cycles; }

  int rounds = 0;
  std::map<std::uint32_t, Cycle> halts;  // pixel -> cycles from its round's start

 private:
  std::uint32_t chunk_size_;
};

// One core of `config` running `program` (by default, in every chunk, `lif r1, 1.0;
// add r2, r1, r1; halt`).
struct CoreRun {
  std::map<Cycle, std::string> issues;  // the core's timeline: cycle -> "chunk i: mnemonic"
  std::map<std::uint32_t, Cycle> halts;
  int rounds = 0;
  Cycle end = 0;
  ShaderCoreTime time;
};

CoreRun run_core(const spec::HardwareConfig& config,
                 const std::string& program = "raygen:\n        lif     r1, 1.0\n        add     r2, r1, r1\n"
                                              "        halt\n") {
  const Scene scene = resolve_scene("tetra:1");
  const functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for(config), IsectMode::kWoop);
  const isa::Firmware firmware =
      isa::assemble("core.s", [&program](const std::filesystem::path&) -> std::optional<std::string> { return program; });
  const fp::Format format = fp::format_by_name(config.format);
  functional::DeviceMemory memory(si.image.bytes, {}, firmware.data, 4);
  const functional::Tracer tracer(si.image.bytes, si.layout, format, config.stack_depth);
  const functional::ShaderCoreConfig core_config = functional::ShaderCoreConfig::of(config, 50'000'000);
  functional::ShaderCore shader(firmware, memory, tracer, format, core_config);

  CoreRun run;
  functional::ShaderStats stats;
  Dram dram(config.dram);
  EventQueue events(1);
  Timeline timeline(0, 1000, 1000, [&run](const TimelineSlice& s) { run.issues[s.begin] = s.name; });
  timeline.start(0, 0);
  OneCoreChip chip(config.chunk_size);
  CoreTiming core(0, config, shader, stats, dram, events, timeline, chip);
  core.start();
  while (const std::optional<EventQueue::Wakeup> w = events.next()) core.run(w->at);
  timeline.flush();
  EXPECT_FALSE(core.live_chunk());
  run.halts = chip.halts;
  run.rounds = chip.rounds;
  run.end = std::max(events.now() + 1, core.accounted());
  run.time = core.finish(run.end);
  return run;
}

// tiny: one core of 4 threads in 2 chunks of 2 lanes.
// Rules: a chunk instruction's lanes enter S0 one a cycle from the cycle after its issue;
// the next chunk instruction may issue in the cycle its last lane enters; the chunk
// issues again `reissue` (E) cycles after its last lane's S0, and a register it wrote is
// ready `result` (R) cycles after that S0; chunks issue round robin from chunk 0. With
// M = max(E, R):
//   chunk 0 lif at 0 (S0 1, 2); chunk 1 lif at 2, the cycle chunk 0's last lane enters
//   (S0 3, 4); chunk 0 add at 2 + M (r1 ready at 2 + R, its reissue at 2 + E) (S0 3 + M,
//   4 + M); chunk 1 add at 4 + M; chunk 0 halt at 4 + M + E (its reissue; add wrote no
//   register halt reads); chunk 1 halt at 6 + M + E, its last lane's S0 at 8 + M + E.
// A halted lane's pixel took halt's issue + 1 cycles. The core is busy from each issue to
// its last lane's S0 (2 + 3 cycles a pair of chunk instructions: the second overlaps the
// first's last S0), and waits for its results in between: busy 15, waiting M + E - 6,
// frame 9 + M + E cycles.
TEST(CoreTiming, IssuesAsCountedByHand) {
  const spec::HardwareConfig config = hardware_config("tiny");
  ASSERT_EQ(config.issue_lanes, 1);
  const Cycle E = static_cast<Cycle>(config.latency.reissue), R = static_cast<Cycle>(config.latency.result);
  const Cycle M = std::max(E, R);
  ASSERT_GE(E, 2u);  // the count assumes a chunk's next issue is not held by the other's lanes

  const CoreRun run = run_core(config);
  EXPECT_EQ(run.issues, (std::map<Cycle, std::string>{{0, "chunk 0: lif"},
                                                      {2, "chunk 1: lif"},
                                                      {2 + M, "chunk 0: add"},
                                                      {4 + M, "chunk 1: add"},
                                                      {4 + M + E, "chunk 0: halt"},
                                                      {6 + M + E, "chunk 1: halt"}}));
  EXPECT_EQ(run.halts, (std::map<std::uint32_t, Cycle>{{0, 5 + M + E}, {1, 5 + M + E}, {2, 7 + M + E}, {3, 7 + M + E}}));
  EXPECT_EQ(run.rounds, 2);
  EXPECT_EQ(run.end, 9 + M + E);
  EXPECT_EQ(run.time.busy, 15u);
  EXPECT_EQ(run.time.wait_dependency, M + E - 6);
  EXPECT_EQ(run.time.wait_trace + run.time.wait_memory + run.time.idle, 0u);
  EXPECT_EQ(run.time.chunk_issues, 6u);
}

// The same with issue_lanes = 2: lif, add and halt are instructions of spec/isa.toml
// [issue], so a chunk's two lanes enter S0 together, the cycle after its issue:
//   chunk 0 lif at 0 (S0 1); chunk 1 lif at 1 (S0 2); chunk 0 add at 1 + M (S0 2 + M);
//   chunk 1 add at 2 + M; chunk 0 halt at 2 + M + E; chunk 1 halt at 3 + M + E (S0
//   4 + M + E). Busy 3 cycles a pair, 9 in all; frame 5 + M + E cycles.
TEST(CoreTiming, IssuesLanesTogether) {
  spec::HardwareConfig config = hardware_config("tiny");
  config.issue_lanes = 2;
  const Cycle E = static_cast<Cycle>(config.latency.reissue), R = static_cast<Cycle>(config.latency.result);
  const Cycle M = std::max(E, R);
  ASSERT_GE(E, 2u);

  const CoreRun run = run_core(config);
  EXPECT_EQ(run.issues, (std::map<Cycle, std::string>{{0, "chunk 0: lif"},
                                                      {1, "chunk 1: lif"},
                                                      {1 + M, "chunk 0: add"},
                                                      {2 + M, "chunk 1: add"},
                                                      {2 + M + E, "chunk 0: halt"},
                                                      {3 + M + E, "chunk 1: halt"}}));
  EXPECT_EQ(run.halts, (std::map<std::uint32_t, Cycle>{{0, 3 + M + E}, {1, 3 + M + E}, {2, 4 + M + E}, {3, 4 + M + E}}));
  EXPECT_EQ(run.end, 5 + M + E);
  EXPECT_EQ(run.time.busy, 9u);
  EXPECT_EQ(run.time.wait_dependency, M + E - 4);
  EXPECT_EQ(run.time.chunk_issues, 6u);
}

// sfu_threads: a chunk's lanes go to sfu (lane mod sfu_threads), each one thread at a
// time. One chunk of tiny's two lanes computing `rcp r2.x, r1`: lane k's value is back
// in S0 at s + k + T + L - 1 + F with two sfus (s its lane 0's S0, T latency.to_unit,
// L latency.sfu + 1 a pass, F latency.from_unit), but lane 1 waits for lane 0's value to
// leave with one sfu, L + F cycles later: the add that reads r2, and the frame, end
// L + F - 1 cycles sooner; each sfu holds a thread L + F cycles.
TEST(CoreTiming, SfusTakeTheirOwnLanes) {
  spec::HardwareConfig config = hardware_config("tiny");
  config.threads_per_core = config.chunk_size;  // one chunk
  ASSERT_EQ(config.chunk_size, 2);
  const Cycle L = static_cast<Cycle>(config.latency.sfu) + 1, F = static_cast<Cycle>(config.latency.from_unit);
  const std::string program =
      "raygen:\n        lif     r1, 2.0\n        rcp     r2.x, r1\n        add     r3, r2, r2\n        halt\n";
  config.sfu_threads = 1;
  const CoreRun one = run_core(config, program);
  config.sfu_threads = 2;
  const CoreRun two = run_core(config, program);
  EXPECT_EQ(one.end - two.end, L + F - 1);
  EXPECT_EQ(one.time.sfu_busy, 2 * (L + F));
  EXPECT_EQ(two.time.sfu_busy, L + F);
  EXPECT_EQ(one.halts.size(), 2u);
  EXPECT_EQ(two.halts.size(), 2u);
}

}  // namespace
}  // namespace rpu::cycle
