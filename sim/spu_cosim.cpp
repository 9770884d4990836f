// The shader core's co-simulation (docs/rtl.md "Shader core"): one Verilated rpu_spu of
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
#include "spu_agents.hpp"
#include "spu_checker.hpp"
#include "spu_model.hpp"

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
};

// `model` outlives the run, so that its waveforms are closed also after a failure.
int run(const Options& o, std::unique_ptr<SpuModel>& model) {
  const spec::HardwareConfig& config = hardware_config(o.config);
  const fp::Format format = fp::format_by_name(std::string(config.format));
  model = make_spu_model(o.config, o.seed, o.trace);
  if (!model) {
    std::string built;
    for (const std::string& n : spu_models()) built += " " + n;
    throw Error(fmt::format("no shader-core model for configuration '{}' in this build (built:{})", o.config, built));
  }

  // The host's side, as `rpu render` does it.
  const KdBuildConfig build = [&] {
    KdBuildConfig b = kd_build_config_for(config);
    b.format = format;
    return b;
  }();
  const Scene scene = functional::chip_space_scene(resolve_scene(o.scene), format);
  const functional::SceneImage si = functional::make_scene_image(scene, build, IsectMode::kWoop);
  const isa::Firmware firmware =
      o.firmware.empty() ? isa::builtin_firmware("whitted.s") : isa::load_firmware_or_assemble(o.firmware);
  if (firmware.code.size() > model->code_words()) {
    throw Error(fmt::format("the firmware has {} instructions; the core's code memory holds {}", firmware.code.size(),
                            model->code_words()));
  }
  const std::vector<std::uint32_t> table =
      o.empty_shader_table ? std::vector<std::uint32_t>{} : device::shader_table(firmware, shader_names(scene));
  const device::Launch launch{o.width, o.height, o.spp, o.max_depth, o.frame_seed};
  const std::vector<std::uint8_t> launch_block = device::make_launch_block(si.image.bytes, si.layout, launch, table);
  const auto pixels = static_cast<std::uint32_t>(o.width * o.height);
  const auto threads = static_cast<std::uint32_t>(config.threads_per_core);

  streams::Launch lf;
  lf.pixels = pixels;
  lf.width = static_cast<std::uint32_t>(o.width);
  lf.height = static_cast<std::uint32_t>(o.height);
  lf.spp = static_cast<std::uint32_t>(o.spp);
  lf.max_depth = static_cast<std::uint32_t>(o.max_depth);
  lf.raygen = functional::raygen_entry(firmware);
  lf.code_words = static_cast<std::uint32_t>(firmware.code.size());
  lf.image_bytes = static_cast<std::uint32_t>(si.image.bytes.size());
  lf.launch_bytes = static_cast<std::uint32_t>(launch_block.size());
  lf.data_bytes = static_cast<std::uint32_t>(firmware.data.size());
  lf.shader_count = static_cast<std::uint32_t>(table.size());
  std::memcpy(&lf.shader_table, launch_block.data() + mm::kLaunchShaderTableAt, 4);
  lf.watchdog = static_cast<std::uint32_t>(o.watchdog);
  const PixelDivisor div = pixel_divisor(lf.width);
  lf.div_magic = div.magic;
  lf.div_shift1 = div.shift1;
  lf.div_shift2 = div.shift2;

  // The RTL's memory, and the functional model's own.
  SparseMemory memory(si.image.bytes, launch_block, firmware.data, pixels,
                      threads * static_cast<std::uint32_t>(config.stack_bytes));
  functional::DeviceMemory golden_memory(si.image.bytes, launch_block, firmware.data, pixels);
  const functional::Tracer tracer(si.image.bytes, si.layout, format, config.stack_depth);

  SpuCheckerSetup cs;
  cs.firmware = &firmware;
  cs.tracer = &tracer;
  cs.format = format;
  cs.core.registers = config.registers;
  cs.core.chunk_size = config.chunk_size;
  cs.core.call_depth = config.call_depth;
  cs.core.stack_bytes = static_cast<std::uint32_t>(config.stack_bytes);
  cs.core.watchdog = o.watchdog;
  cs.threads_per_core = threads;
  cs.total_threads = threads;
  cs.pixels = pixels;
  cs.width = lf.width;
  SpuChecker checker(cs, golden_memory);

  Stalls stalls(o.seed, o.stall);
  CachePortServer mem_server(memory, o.memory, stalls.rng());
  RayServer ray_server(tracer, o.rays, stalls.rng());

  Clock<SpuModel> clock(*model);
  SpuInputs in;
  in.launch = lf;
  clock.reset(in);
  for (std::uint32_t pc = 0; pc < firmware.code.size(); ++pc) {
    in.code_we = true;
    in.code_addr = pc;
    in.code_data = firmware.code[pc];
    clock.settle(in);
    clock.tick();
  }
  in.code_we = false;
  in.start = true;
  clock.settle(in);
  clock.tick();
  in.start = false;

  const auto start = std::chrono::steady_clock::now();
  std::optional<std::uint32_t> stop_pixel;
  Watchdog watchdog(100'000);
  std::uint64_t cycle = 0;
  for (;; ++cycle) {
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

    const SpuOutputs out = clock.settle(in);
    if (out.done && mem_server.idle() && ray_server.idle()) break;
    if (now > o.max_cycles) throw CosimFailure(fmt::format("the frame did not end in {} cycles", o.max_cycles));

    // Trace ports first: a writeback before the issue of the same cycle (docs/rtl.md).
    if (out.wb_valid) checker.on_writeback(out.wb, now);
    if (out.fault_valid) {
      checker.on_fault(out.fault, now);
      if (!stop_pixel || out.fault.pixel < *stop_pixel) stop_pixel = out.fault.pixel;
    }
    if (out.retire_valid) checker.on_retire(out.retire, now);
    if (out.issue_valid) checker.on_issue(out.issue, now);
    bool progress = out.issue_valid || out.retire_valid || out.wb_valid;

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
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::uint64_t cycles = clock.cycle();
  fmt::print("spu_cosim ok: config {}, {} ({}), {}x{} pixels, {} cycles, {} chunk steps, {} instructions, {} rays, "
             "{:.2f} s, {:.0f} cycles/s\n",
             o.config, scene.source, format.name(), o.width, o.height, cycles, checker.steps(), checker.retired(),
             ray_server.rays(), seconds, static_cast<double>(cycles) / std::max(seconds, 1e-9));
  if (const functional::ShaderFault* f = checker.first_fault()) {
    fmt::print("the frame faulted, the same on both: {}\n", f->what());
  }
  return 0;
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
  app.add_option("--seed", o.seed, "seed of the RTL's initial values and of the agents' stalls and delays");
  app.add_option("--stall", o.stall, "probability that a ready or an answer stalls in a cycle")->check(CLI::Range(0.0, 0.9));
  app.add_option("--max-cycles", o.max_cycles, "give up after this many cycles");
  app.add_option("--trace", o.trace, "write FST waveforms here");
  app.add_flag("--empty-shader-table", o.empty_shader_table,
               "launch with no shaders (as tests/isa runs its programs), not the scene's");
  CLI11_PARSE(app, argc, argv);
  report_sigbus_as_write_failure("spu_cosim");
  std::unique_ptr<SpuModel> model;
  int status = 0;
  try {
    check_output_paths(o.trace, "");
    status = run(o, model);
  } catch (const CosimFailure& e) {
    fmt::print(stderr, "spu_cosim FAIL: {}\n", e.what());
    status = 1;
  } catch (const Error& e) {
    fmt::print(stderr, "spu_cosim: {}\n", e.what());
    status = 2;
  }
  try {
    if (model) model->close_trace();
  } catch (const Error& e) {
    fmt::print(stderr, "spu_cosim: {}\n", e.what());
    status = 2;
  }
  return status;
}
