// The shader core's co-simulation (docs/chip.md "Shader core"): one Verilated rpu_spu of
// a named configuration renders a frame of firmware over a scene while the lockstep
// checker (sim/spu_checker.hpp) steps the functional model and compares every issue,
// retire, writeback and fault record. The core's memory port is served from the
// device's address space and its ray port by the functional tracer, both after random
// delays in any order; every ready stalls at random. At the end the framebuffer the
// core wrote must equal the functional model's, byte for byte.
//
//   spu_cosim --config tiny --scene cornell --width 8 --height 8 [--firmware FILE]
//             [--seed N] [--stall P] [--trace waves.fst]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "asm/firmware_file.hpp"
#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "cosim_core.hpp"
#include "device/device.hpp"
#include "functional/scene_image.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"
#include "common/output_file.hpp"
#include "harness_outputs.hpp"
#include "host_setup.hpp"
#include "model.hpp"
#include "spu_agents.hpp"
#include "spu_checker.hpp"
#include "progen/coverage.hpp"
#include "progen/progen.hpp"
#include "rpu/harness/spu.hpp"

namespace {

using namespace rpu;
using namespace rpu::sim;
namespace mm = spec::memory;

struct Options {
  std::string config = "tiny";
  std::string scene = "cornell";
  std::string firmware;
  int width = 8, height = 8, spp = 1, max_depth = 2;
  std::uint32_t frame_seed = 1;
  std::uint64_t watchdog = 1'000'000;
  std::uint64_t seed = 1;
  double stall = 0.08;
  AgentTiming memory{4, 12};
  AgentTiming rays{8, 40};
  std::uint64_t max_cycles = 200'000'000;
  std::string trace;
  bool empty_shader_table = false;
  int issue_lanes = 0;  // the core model's issue lanes; 0: the configuration's
  int sfu_threads = 0;  // the core model's sfus; 0: the configuration's
  // Random programs (sim/progen): how many, and every how many a fault program.
  std::uint64_t random = 0;
  std::uint64_t fault_every = 5;
  int statements = 0;  // progen's max_statements per block; 0: its default
  bool coverage = false;
  bool require_coverage = false;
};

// The chip's side a frame needs besides the firmware: the configuration and the scene.
struct Bench {
  const spec::HardwareConfig& config;
  fp::Format format;
  functional::SceneImage scene;
  std::vector<std::string> shader_names;
  std::unique_ptr<functional::Tracer> tracer;

  Bench(const spec::HardwareConfig& c, const std::string& scene_arg)
      : config(c), format(fp::format_by_name(std::string(c.format))) {
    KdBuildConfig build = kd_build_config_for(c);
    build.format = format;
    const Scene s = functional::chip_space_scene(resolve_scene(scene_arg), format);
    scene = functional::make_scene_image(s, build, IsectMode::kWoop);
    shader_names = rpu::shader_names(s);
    tracer = std::make_unique<functional::Tracer>(scene.image.bytes, scene.layout, format, c.stack_depth);
  }
};

struct Frame {
  const isa::Firmware* firmware = nullptr;
  std::vector<std::uint32_t> shader_table;
  device::Launch launch;
  std::uint64_t watchdog = 0;
};

struct FrameResult {
  std::uint64_t cycles = 0, steps = 0, retired = 0, rays = 0;
  std::optional<std::string> fault;  // the first fault in pixel order, the same on both
  std::optional<std::uint32_t> fault_pixel;
};

// One frame on a fresh model in lockstep; CosimFailure at the first difference.
// `observer` sees the functional model's steps (coverage).
FrameResult run_frame(const Options& o, const Bench& bench, const Frame& frame, std::uint64_t seed,
                      const std::string& fst, std::unique_ptr<Model<harness::Spu>>& model,
                      progen::StepObserver* observer = nullptr) {
  const spec::HardwareConfig& config = bench.config;
  const isa::Firmware& firmware = *frame.firmware;
  // The issue lanes and the sfus change only the cycles (docs/shader-core.md "Issue"): the
  // checker expects the same records of a core built with others than the configuration's.
  const std::string lanes = std::to_string(o.issue_lanes ? o.issue_lanes : config.issue_lanes);
  const std::string sfus = std::to_string(o.sfu_threads ? o.sfu_threads : config.sfu_threads);
  const ModelInfo* info =
      find_model<harness::Spu>({{"config", config.name}, {"issue_lanes", lanes}, {"sfu_threads", sfus}});
  if (!info) {
    throw Error(fmt::format("no shader-core model for configuration '{}' with {} issue lanes and {} sfus in this build "
                            "(built: {})",
                            config.name, lanes, sfus, built_models<harness::Spu>()));
  }
  model = make_model<harness::Spu>(*info, seed, fst);
  const auto ways = static_cast<std::size_t>(info->number("issue_lanes"));
  if (firmware.code.size() > static_cast<std::size_t>(info->number("code_words"))) {
    throw Error(fmt::format("the firmware has {} instructions; the core's code memory holds {}", firmware.code.size(),
                            info->number("code_words")));
  }
  const functional::SceneImage& si = bench.scene;
  const device::Launch& launch = frame.launch;
  const std::vector<std::uint8_t> launch_block =
      device::make_launch_block(si.image.bytes, si.layout, launch, frame.shader_table);
  const auto pixels = static_cast<std::uint32_t>(launch.width * launch.height);
  const auto threads = static_cast<std::uint32_t>(config.threads_per_core);

  LaunchFacts facts;
  facts.width = static_cast<std::uint32_t>(launch.width);
  facts.height = static_cast<std::uint32_t>(launch.height);
  facts.spp = static_cast<std::uint32_t>(launch.spp);
  facts.max_depth = static_cast<std::uint32_t>(launch.max_depth);
  facts.raygen = functional::raygen_entry(firmware);
  facts.code_words = static_cast<std::uint32_t>(firmware.code.size());
  facts.image_bytes = static_cast<std::uint32_t>(si.image.bytes.size());
  facts.launch_block = launch_block;
  facts.data_bytes = static_cast<std::uint32_t>(firmware.data.size());
  facts.watchdog = frame.watchdog;
  const streams::Launch lf = launch_stream(facts);

  // The RTL's memory, and the functional model's own.
  SparseMemory memory(si.image.bytes, launch_block, firmware.data, pixels,
                      functional::stack_region_bytes(threads, static_cast<std::uint32_t>(config.stack_bytes)));
  functional::DeviceMemory golden_memory(si.image.bytes, launch_block, firmware.data, pixels);

  SpuCheckerSetup cs;
  cs.firmware = &firmware;
  cs.tracer = bench.tracer.get();
  cs.format = bench.format;
  cs.core = functional::ShaderCoreConfig::of(config, frame.watchdog);
  cs.threads_per_core = threads;
  cs.pixels = pixels;
  cs.width = lf.width;
  cs.observer = observer;
  SpuChecker checker(cs, golden_memory);

  Stalls stalls(seed, o.stall);
  CachePortServer mem_server(memory, o.memory, stalls.rng());
  RayServer ray_server(*bench.tracer, o.rays, stalls.rng());

  Clock<Model<harness::Spu>> clock(*model);
  harness::Spu::Inputs in;
  in.launch = lf;
  clock.reset(in);
  const std::uint64_t first_cycle = write_code_and_start(clock, in, firmware.code);

  std::optional<std::uint32_t> stop_pixel;
  Watchdog watchdog(100'000);
  for (;;) {
    const std::uint64_t now = clock.cycle();
    in.cache_req_ready = !stalls();
    const streams::CacheRsp* mem_rsp = stalls() ? nullptr : mem_server.offer(now);
    in.cache_rsp_valid = mem_rsp != nullptr;
    if (mem_rsp) in.cache_rsp = *mem_rsp;
    in.trace_req_ready = !stalls();
    const streams::TraceRsp* ray_rsp = stalls() ? nullptr : ray_server.offer(now);
    in.trace_rsp_valid = ray_rsp != nullptr;
    if (ray_rsp) in.trace_rsp = *ray_rsp;
    in.stop = stop_pixel.has_value();
    in.stop_pixel = stop_pixel.value_or(0);

    const harness::Spu::Outputs out = clock.settle(in);
    if (out.done && mem_server.idle() && ray_server.idle()) break;
    if (now - first_cycle > o.max_cycles) {
      throw CosimFailure(fmt::format("the frame did not end in {} cycles", o.max_cycles));
    }

    // Trace ports first: a writeback before the issue of the same cycle (docs/rtl.md).
    // The ways' records in lane order.
    bool progress = out.issue_valid;
    for (std::size_t v = 0; v < ways; ++v) {
      if (out.wb_valid[v]) checker.on_writeback(out.wb[v], now);
      progress |= out.wb_valid[v] || out.retire_valid[v];
    }
    if (out.fault_valid) {
      checker.on_fault(out.fault, now);
      if (!stop_pixel || out.fault.pixel < *stop_pixel) stop_pixel = out.fault.pixel;
    }
    for (std::size_t v = 0; v < ways; ++v) {
      if (out.retire_valid[v]) checker.on_retire(out.retire[v], now);
    }
    if (out.issue_valid) checker.on_issue(out.issue, now);

    if (out.cache_req_valid && in.cache_req_ready) mem_server.take(out.cache_req, now);
    if (in.cache_rsp_valid && out.cache_rsp_ready) mem_server.taken();
    if (out.trace_req_valid && in.trace_req_ready) ray_server.take(out.trace_req, now);
    if (in.trace_rsp_valid && out.trace_rsp_ready) {
      ray_server.taken();
      progress = true;
    }
    if (progress) watchdog.progress(now);
    watchdog.check(now, true, [] { return std::string("the core, which has not finished its frame"); });
    clock.tick();
  }
  checker.finish(stop_pixel);

  const std::vector<std::uint8_t> fb = memory.read(mm::kDeviceFramebufferBase, pixels * mm::kFramebufferBytesPerPixel);
  const std::span<const std::uint8_t> golden = golden_memory.framebuffer();
  for (std::uint32_t i = 0; i < fb.size(); i += 4) {
    if (std::memcmp(fb.data() + i, golden.data() + i, 4) != 0) {
      std::uint32_t got, want;
      std::memcpy(&got, fb.data() + i, 4);
      std::memcpy(&want, golden.data() + i, 4);
      const std::uint32_t p = i / mm::kFramebufferBytesPerPixel;
      throw CosimFailure(fmt::format("framebuffer of pixel {} ({}, {}) lane {}: the functional model wrote {:#010x}, "
                                     "the core {:#010x}",
                                     p, p % lf.width, p / lf.width, i / 4 % 4, want, got));
    }
  }
  FrameResult r;
  r.cycles = clock.cycle() - first_cycle;
  r.steps = checker.steps();
  r.retired = checker.retired();
  r.rays = ray_server.rays();
  if (const functional::ShaderFault* f = checker.first_fault()) {
    r.fault = f->what();
    r.fault_pixel = f->pixel();
  }
  return r;
}

// One frame of firmware over a scene (the default mode).
int run_firmware(const Options& o, std::unique_ptr<Model<harness::Spu>>& model) {
  const Bench bench(hardware_config(o.config), o.scene);
  const isa::Firmware firmware =
      o.firmware.empty() ? isa::builtin_firmware("whitted.s") : isa::load_firmware_or_assemble(o.firmware);
  Frame frame;
  frame.firmware = &firmware;
  frame.shader_table =
      o.empty_shader_table ? std::vector<std::uint32_t>{} : device::shader_table(firmware, bench.shader_names);
  frame.launch = {o.width, o.height, o.spp, o.max_depth, o.frame_seed};
  frame.watchdog = o.watchdog;
  const auto start = std::chrono::steady_clock::now();
  const FrameResult r = run_frame(o, bench, frame, o.seed, o.trace, model);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("spu_cosim ok: config {}, {} ({}), {}x{} pixels, {} cycles, {} chunk steps, {} instructions, {} rays, "
             "{:.2f} s, {:.0f} cycles/s\n",
             o.config, o.scene, bench.format.name(), o.width, o.height, r.cycles, r.steps, r.retired, r.rays, seconds,
             static_cast<double>(r.cycles) / std::max(seconds, 1e-9));
  if (r.fault) fmt::print("the frame faulted, the same on both: {}\n", *r.fault);
  return 0;
}

// Random programs (docs/random-programs.md), each a frame in lockstep on a fresh model;
// every fault_every-th one ends in a fault class, the classes in turn. A failing
// program is shrunk to a small one that still fails, and printed.
int run_random(const Options& o, std::unique_ptr<Model<harness::Spu>>& model) {
  const spec::HardwareConfig& config = hardware_config(o.config);
  const Bench bench(config, o.scene);
  progen::Options po = progen::Options::for_config(config);
  if (o.statements > 0) po.max_statements = o.statements;
  progen::Coverage coverage;
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t cycles = 0, retired = 0, faults = 0;
  std::size_t next_fault = 0;
  for (std::uint64_t i = 0; i < o.random; ++i) {
    const std::uint64_t seed = o.seed + i;
    po.fault = progen::FaultClass::kNone;
    if (o.fault_every && i % o.fault_every == o.fault_every - 1) {
      po.fault = progen::kFaultClasses[next_fault++ % progen::kFaultClasses.size()].fault;
    }
    const progen::Program program = progen::generate(seed, po);
    const auto frame_of = [&](const progen::Program& p, const isa::Firmware& fw) {
      Frame f;
      f.firmware = &fw;
      f.shader_table = device::shader_table(fw, p.shader_names());
      f.launch = {o.width, o.height, 1, 0, 1};
      f.watchdog = p.watchdog();
      return f;
    };
    const isa::Firmware firmware = program.firmware();
    progen::Coverage mine;
    try {
      const FrameResult r = run_frame(o, bench, frame_of(program, firmware), seed, "", model, &mine);
      progen::Outcome outcome;
      outcome.fault = r.fault;
      outcome.fault_pixel = r.fault_pixel;
      outcome.steps = r.steps;
      outcome.instructions = r.retired;
      mine.add_outcome(outcome);
      coverage += mine;
      cycles += r.cycles;
      retired += r.retired;
      faults += r.fault.has_value();
    } catch (const CosimFailure& first) {
      fmt::print(stderr, "spu_cosim: random program {} (seed {}, {}) fails: {}\nshrinking...\n", i, seed,
                 progen::fault_name(po.fault), first.what());
      std::string last = first.what();
      const progen::Program small = progen::shrink(program, [&](const progen::Program& p) {
        const isa::Firmware fw = p.firmware();
        std::unique_ptr<Model<harness::Spu>> m;
        try {
          run_frame(o, bench, frame_of(p, fw), seed, "", m);
          return false;
        } catch (const CosimFailure& e) {
          last = e.what();
          return true;
        }
      });
      throw CosimFailure(fmt::format("random program seed {} ({}), shrunk to:\n{}\nwhich fails with: {}", seed,
                                     progen::fault_name(po.fault), small.assembly(), last));
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("spu_cosim ok: config {}, {} random programs from seed {} in lockstep ({} ended in a fault), {} cycles, "
             "{} instructions, {:.1f} s, {:.0f} cycles/s\n",
             o.config, o.random, o.seed, faults, cycles, retired, seconds,
             static_cast<double>(cycles) / std::max(seconds, 1e-9));
  if (o.coverage) fmt::print("{}", coverage.report());
  if (o.require_coverage && !coverage.complete()) {
    std::string missing;
    for (const std::string& m : coverage.missing()) missing += "\n  " + m;
    throw CosimFailure("the random programs left uncovered:" + missing);
  }
  return 0;
}

// `model` outlives the run, so that its waveforms are closed also after a failure.
int run(const Options& o, std::unique_ptr<Model<harness::Spu>>& model) {
  return o.random ? run_random(o, model) : run_firmware(o, model);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Co-simulate one RTL shader core in lockstep with the functional model (docs/rtl.md)"};
  Options o;
  app.add_option("--config", o.config, "named hardware configuration (spec/configs.toml)");
  app.add_option("--scene", o.scene, "scene file or built-in scene, as rpu render takes it");
  app.add_option("--firmware", o.firmware, "firmware (.s or .rfw); default the built-in whitted.s");
  app.add_option("--width", o.width, "pixels")->check(CLI::Range(1, 4096));
  app.add_option("--height", o.height, "pixels")->check(CLI::Range(1, 4096));
  app.add_option("--spp", o.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  app.add_option("--max-depth", o.max_depth, "bounces")->check(CLI::Range(0, 64));
  app.add_option("--watchdog", o.watchdog, "instructions a thread may retire for one pixel")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{0xffffffff}));
  app.add_option("--issue-lanes", o.issue_lanes, "run the core built with this many issue lanes (default: the "
                 "configuration's)")->check(CLI::IsMember({1, 2, 4, 8}));
  app.add_option("--sfu-threads", o.sfu_threads, "run the core built with this many sfus (default: the "
                 "configuration's)")->check(CLI::IsMember({1, 2, 4, 8}));
  app.add_option("--seed", o.seed, "seed of the RTL's initial values and of the agents' stalls and delays");
  app.add_option("--stall", o.stall, "probability that a ready or an answer stalls in a cycle")->check(CLI::Range(0.0, 0.9));
  app.add_option("--max-cycles", o.max_cycles, "give up after this many cycles");
  app.add_option("--trace", o.trace, "write FST waveforms here");
  app.add_flag("--empty-shader-table", o.empty_shader_table,
               "launch with no shaders (as tests/isa runs its programs), not the scene's");
  app.add_option("--random", o.random, "run this many random programs (sim/progen) from --seed instead of firmware");
  app.add_option("--fault-every", o.fault_every, "every how many random programs one ends in a fault (0: none)");
  app.add_option("--statements", o.statements, "statements per block of a random program (default: progen's)")
      ->check(CLI::Range(1, 100));
  app.add_flag("--coverage", o.coverage, "print the random programs' coverage");
  app.add_flag("--require-coverage", o.require_coverage,
               "fail unless the random programs covered every instruction, event and fault class");
  CLI11_PARSE(app, argc, argv);
  report_sigbus_as_write_failure("spu_cosim");
  std::unique_ptr<Model<harness::Spu>> model;
  return run_harness("spu_cosim", o.trace, "", model, [&o](std::unique_ptr<Model<harness::Spu>>& m) { return run(o, m); });
}
