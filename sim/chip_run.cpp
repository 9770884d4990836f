#include "chip_run.hpp"

#include <cstring>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "common/error.hpp"
#include "cosim_core.hpp"
#include "device_dram.hpp"
#include "functional/device_memory.hpp"
#include "functional/tracer.hpp"
#include "host_setup.hpp"
#include "isa/instruction.hpp"
#include "spu_checker.hpp"

namespace rpu::sim {

namespace mm = spec::memory;
namespace si = spec::isa;

namespace {

// The counters' own arithmetic (docs/chip.md "Statistics"): every unit's time adds up to
// the frame's counted cycles, and every cache's reads to hits, merges and misses; the
// counters are 32 bits wide and wrap, so the sums are compared modulo 2^32.
void check_counters(const ChipCounters& k, std::uint64_t cycles) {
  const auto wrap = [](std::uint64_t v) { return static_cast<std::uint32_t>(v); };
  for (std::size_t c = 0; c < k.cores.size(); ++c) {
    const streams::CoreCounters& t = k.cores[c];
    const std::uint64_t sum = std::uint64_t{t.busy} + t.wait_dependency + t.wait_memory + t.wait_trace + t.idle;
    if (wrap(sum) != wrap(cycles)) {
      throw CosimFailure(fmt::format("core {}'s counters add up to {} cycles (busy {}, waits {} / {} / {}, idle {}), "
                                     "the frame took {}",
                                     c, sum, t.busy, t.wait_dependency, t.wait_memory, t.wait_trace, t.idle, cycles));
    }
  }
  for (std::size_t u = 0; u < k.ray_units.size(); ++u) {
    const streams::RayUnitCounters& t = k.ray_units[u];
    const std::uint64_t sum = std::uint64_t{t.busy} + t.wait_memory + t.wait_iu + t.idle;
    if (wrap(sum) != wrap(cycles)) {
      throw CosimFailure(fmt::format("ray unit {}'s counters add up to {} cycles (busy {}, waits {} / {}, idle {}), "
                                     "the frame took {}",
                                     u, sum, t.busy, t.wait_memory, t.wait_iu, t.idle, cycles));
    }
  }
  for (std::size_t c = 0; c < k.caches.size(); ++c) {
    const streams::CacheCounters& t = k.caches[c];
    if (wrap(std::uint64_t{t.hits} + t.merged + t.misses) != t.accesses) {
      throw CosimFailure(fmt::format("cache {}: {} reads, but {} hits + {} merged + {} misses", c, t.accesses, t.hits,
                                     t.merged, t.misses));
    }
  }
}

}  // namespace

ChipRunResult run_chip_frame(Model<harness::Chip>& model, const ModelInfo& info, const ChipFrame& frame,
                             const ChipRunOptions& options) {
  const spec::HardwareConfig& config = *frame.config;
  const isa::Firmware& firmware = *frame.firmware;
  const int cores = info.number("cores");
  // Each core's retire and writeback records, one per way (rpu_spu), in lane order.
  const auto ways = static_cast<std::size_t>(info.number("issue_lanes"));
  if (firmware.code.size() > static_cast<std::size_t>(info.number("code_words"))) {
    throw Error(fmt::format("the firmware has {} instructions; the chip's code memories hold {}",
                            firmware.code.size(), info.number("code_words")));
  }
  const auto pixels = static_cast<std::uint32_t>(frame.launch.width) * static_cast<std::uint32_t>(frame.launch.height);
  const auto threads = static_cast<std::uint32_t>(config.shader_cores * config.threads_per_core);

  LaunchFacts facts;
  facts.width = static_cast<std::uint32_t>(frame.launch.width);
  facts.height = static_cast<std::uint32_t>(frame.launch.height);
  facts.spp = static_cast<std::uint32_t>(frame.launch.spp);
  facts.max_depth = static_cast<std::uint32_t>(frame.launch.max_depth);
  facts.raygen = functional::raygen_entry(firmware);
  facts.code_words = static_cast<std::uint32_t>(firmware.code.size());
  facts.image_bytes = static_cast<std::uint32_t>(frame.image.size());
  facts.launch_block = frame.launch_block;
  facts.data_bytes = static_cast<std::uint32_t>(firmware.data.size());
  facts.watchdog = frame.watchdog;

  SparseMemory memory(frame.image, frame.launch_block, firmware.data, pixels,
                      functional::stack_region_bytes(threads, static_cast<std::uint32_t>(config.stack_bytes)));
  DeviceDram dram(memory, config.dram);

  // The lockstep: the functional model with its own memory, a checker per core.
  std::unique_ptr<functional::DeviceMemory> golden;
  std::unique_ptr<functional::Tracer> tracer;
  std::vector<std::unique_ptr<SpuChecker>> checkers;
  if (options.lockstep) {
    golden = std::make_unique<functional::DeviceMemory>(
        frame.image, std::vector<std::uint8_t>(frame.launch_block.begin(), frame.launch_block.end()), firmware.data,
        pixels);
    tracer = std::make_unique<functional::Tracer>(frame.image, *frame.layout, frame.format, config.stack_depth);
    for (int c = 0; c < cores; ++c) {
      SpuCheckerSetup cs;
      cs.firmware = &firmware;
      cs.tracer = tracer.get();
      cs.format = frame.format;
      cs.core = functional::ShaderCoreConfig::of(config, frame.watchdog);
      cs.core_id = static_cast<std::uint32_t>(c);
      cs.threads_per_core = static_cast<std::uint32_t>(config.threads_per_core);
      cs.cores = static_cast<std::uint32_t>(cores);
      cs.pixels = pixels;
      cs.width = facts.width;
      checkers.push_back(std::make_unique<SpuChecker>(cs, *golden));
    }
  }

  Clock<Model<harness::Chip>> clock(model);
  harness::Chip::Inputs in;
  in.launch = launch_stream(facts);
  in.tu_cfg = tu_config(*frame.layout);
  clock.reset(in);
  const std::uint64_t first = write_code_and_start(clock, in, firmware.code);
  in.dram_req_ready = true;

  ChipRunResult result;
  std::optional<std::uint64_t> done_at;
  std::uint64_t halted = 0;
  Watchdog watchdog(1'000'000);
  for (;;) {
    const std::uint64_t now = clock.cycle();
    const streams::DramRsp* rsp = dram.offer(now);
    in.dram_rsp_valid = rsp != nullptr;
    if (rsp) in.dram_rsp = *rsp;
    const harness::Chip::Outputs out = clock.settle(in);
    if (out.done && !done_at) done_at = now;
    if (out.done && dram.idle()) break;
    if (options.max_cycles && now - first > options.max_cycles) {
      throw CosimFailure(fmt::format("the frame did not end in {} cycles", options.max_cycles));
    }
    bool progress = false;
    for (std::size_t c = 0; c < static_cast<std::size_t>(cores); ++c) {
      SpuChecker* check = options.lockstep ? checkers[c].get() : nullptr;
      // A writeback before the issue of the same cycle (docs/chip.md "Lockstep co-simulation").
      for (std::size_t v = c * ways; v < (c + 1) * ways; ++v) {
        if (out.wb_valid[v] && check) check->on_writeback(out.wb[v], now);
        progress |= out.wb_valid[v] || out.retire_valid[v];
      }
      if (out.fault_valid[c]) {
        const streams::Fault& f = out.fault[c];
        if (check) check->on_fault(f, now);
        if (!result.fault || f.pixel < result.fault->pixel) {
          result.fault = ChipFault{f.kind, f.core, f.thread, f.pixel, f.pc, f.addr};
        }
      }
      for (std::size_t v = c * ways; v < (c + 1) * ways; ++v) {
        if (!out.retire_valid[v]) continue;
        if (check) check->on_retire(out.retire[v], now);
        const auto opcode = static_cast<si::Opcode>(out.retire[v].insn[0] & ((1u << si::kOpcodeField.width) - 1));
        if (const si::InsnSpec* s = isa::find_insn(opcode)) {
          ++result.retired[static_cast<std::size_t>(s->cls)];
          if (opcode == si::Opcode::kTrace) ++result.closest_rays;
          if (opcode == si::Opcode::kTracea) ++result.any_rays;
          if (opcode == si::Opcode::kHalt && options.progress) options.progress(++halted, pixels);
        }
      }
      if (out.issue_valid[c]) {
        ++result.chunk_issues;
        if (check) check->on_issue(out.issue[c], now);
      }
      progress |= out.issue_valid[c];
    }
    if (out.dram_req_valid) dram.take(out.dram_req, now);
    if (in.dram_rsp_valid && out.dram_rsp_ready) {
      dram.taken();
      progress = true;
    }
    if (progress) watchdog.progress(now);
    watchdog.check(now, true, [] { return std::string("the chip, which has not finished its frame"); });
    clock.tick();
  }
  result.cycles = clock.cycle() - first;
  result.counted_cycles = *done_at - first;
  harness::Chip::Outputs counters;
  model.read_on_demand(counters);
  const auto ray_units = static_cast<std::size_t>(info.number("ray_units"));
  result.counters.cores.assign(counters.core_counters.begin(), counters.core_counters.begin() + cores);
  result.counters.ray_units.assign(counters.ray_counters.begin(), counters.ray_counters.begin() + ray_units);
  result.counters.ray_caches = static_cast<std::size_t>(info.number("ray_caches"));
  result.counters.caches.assign(counters.cache_counters.begin(),
                                counters.cache_counters.begin() + 2 * result.counters.ray_caches + cores);
  check_counters(result.counters, result.counted_cycles);
  result.dram = dram.stats();
  result.framebuffer = memory.read(mm::kDeviceFramebufferBase, pixels * mm::kFramebufferBytesPerPixel);

  if (options.lockstep) {
    for (const auto& check : checkers) {
      check->finish(result.fault ? std::optional<std::uint32_t>(result.fault->pixel) : std::nullopt);
      result.lockstep_steps += check->steps();
    }
    const std::span<const std::uint8_t> want = golden->framebuffer();
    for (std::uint32_t i = 0; i < result.framebuffer.size(); i += 4) {
      if (std::memcmp(result.framebuffer.data() + i, want.data() + i, 4) != 0) {
        std::uint32_t got, expected;
        std::memcpy(&got, result.framebuffer.data() + i, 4);
        std::memcpy(&expected, want.data() + i, 4);
        const std::uint32_t p = i / mm::kFramebufferBytesPerPixel;
        throw CosimFailure(fmt::format("framebuffer of pixel {} ({}, {}) lane {}: the functional model wrote {:#010x}, "
                                       "the chip {:#010x}",
                                       p, p % facts.width, p / facts.width, i / 4 % 4, expected, got));
      }
    }
  }
  return result;
}

}  // namespace rpu::sim
