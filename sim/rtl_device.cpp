// The rtl backend: a frame on the Verilated chip (sim/chip_run.hpp).
#include "rtl_device.hpp"

#include <chrono>
#include <cstring>

#include <fmt/format.h>

#include "chip_run.hpp"
#include "common/error.hpp"
#include "config/config.hpp"
#include "cycle/cycle_stats.hpp"
#include "device/device_base.hpp"
#include "functional/tracer.hpp"

namespace rpu::sim {

namespace {

std::string isect_name(IsectMode m) { return m == IsectMode::kWoop ? "woop" : "watertight"; }

// The Verilated chip of configuration `config` with `isect`; rpu::Error naming the
// chips built when there is none.
const ModelInfo& chip_model(std::string_view config, IsectMode isect) {
  const ModelInfo* info = find_model<harness::Chip>({{"config", config}, {"isect", isect_name(isect)}});
  if (!info) {
    throw Error(fmt::format("no RTL chip model for configuration '{}' with the {} test in this build (built: {})",
                            config, isect_name(isect), rtl_models_built()));
  }
  return *info;
}

class RtlDevice final : public device::DeviceBase {
 public:
  RtlDevice(const spec::HardwareConfig& config, fp::Format format, const RtlOptions& options)
      : DeviceBase(config, format), options_(options) {}
  ~RtlDevice() override { end_frame(); }

  std::string_view backend() const override { return "rtl"; }

 private:
  void run(const ProgressCallback& progress) override;
  // The fault of the RTL's first faulting pixel, with the functional model's message for
  // that pixel (which must agree on kind, pc and address).
  [[noreturn]] void throw_fault(const ChipFault& f) const;

  // The frame's statistics in the cycle backend's form, from the chip's counters.
  cycle::CycleStats cycle_stats(const ChipRunResult& r) const;

  RtlOptions options_;
  cycle::CycleStats frame_;  // the frame's: a selected frame's two launches added
  std::uint64_t lockstep_steps_ = 0;
};

cycle::CycleStats RtlDevice::cycle_stats(const ChipRunResult& r) const {
  cycle::CycleStats s;
  s.config = std::string(config_.name);
  s.clock_mhz = config_.clock_mhz;
  s.cycles = r.cycles;
  s.closest_rays = r.closest_rays;
  s.any_rays = r.any_rays;
  for (const std::uint64_t n : r.retired) s.thread_instructions += n;
  s.dram = r.dram;
  s.dram_bytes_per_cycle = config_.dram.bytes_per_cycle;
  s.counts_pops = false;
  // The cycles after done_o, while the memory finishes its last writes, every unit idles.
  const std::uint64_t tail = r.cycles - r.counted_cycles;
  for (const streams::CoreCounters& k : r.counters.cores) {
    cycle::ShaderCoreTime& t = s.cores.emplace_back();
    t.busy = k.busy;
    t.wait_trace = k.wait_trace;
    t.wait_memory = k.wait_memory;
    t.wait_dependency = k.wait_dependency;
    t.idle = k.idle + tail;
    t.chunk_issues = k.chunk_issues;
  }
  for (const streams::RayUnitCounters& k : r.counters.ray_units) {
    cycle::TraversalUnitTime& t = s.tus.emplace_back();
    t.busy = k.busy;
    t.wait_memory = k.wait_memory;
    t.wait_iu = k.wait_iu;
    t.idle = k.idle + tail;
    t.rays = k.rays;
    t.inner = k.nodes - k.leaves;
    t.leaves = k.leaves;
    t.refs = k.tests;  // the unit tests every reference of a leaf it visits
    t.tests = k.tests;
    // The IU works while its TU waits for it.
    s.ius.push_back({.tests = k.tests, .busy = k.wait_iu});
  }
  const auto cache = [](const streams::CacheCounters& k) {
    cycle::CacheStats c;
    c.accesses = k.accesses;
    c.hits = k.hits;
    c.merged = k.merged;
    c.misses = k.misses;
    c.writes = k.writes;
    c.write_backs = k.write_backs;
    c.mshr_wait_cycles = k.mshr_wait;
    return c;
  };
  const std::size_t pairs = r.counters.ray_caches;
  for (std::size_t p = 0; p < pairs; ++p) {
    s.add_ray_caches(cache(r.counters.caches.at(p)), cache(r.counters.caches.at(pairs + p)));
  }
  for (std::size_t c = 2 * pairs; c < r.counters.caches.size(); ++c) s.data_cache += cache(r.counters.caches[c]);
  return s;
}

void RtlDevice::run(const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (layout_.isect_mode != options_.isect) {
    throw Error(fmt::format("the image's intersection mode is {}, the rtl backend's chip {}",
                            isect_name(layout_.isect_mode), isect_name(options_.isect)));
  }
  const ModelInfo& info = chip_model(config_.name, options_.isect);
  std::unique_ptr<Model<harness::Chip>> model = make_model<harness::Chip>(info, 1, options_.waves);
  model->set_wave_window(options_.wave_begin, options_.wave_end);
  ChipFrame frame;
  frame.config = &config_;
  frame.format = format_;
  frame.image = image_;
  frame.layout = &layout_;
  frame.firmware = &firmware_;
  frame.launch_block = memory_->launch_block();
  frame.launch = launch_;
  frame.watchdog = options_.watchdog;
  ChipRunOptions run;
  run.lockstep = options_.lockstep;
  if (progress) run.progress = [&progress](std::uint64_t done, std::uint64_t total) { progress(done, total); };
  ChipRunResult r;
  try {
    r = run_chip_frame(*model, info, frame, run);
  } catch (...) {
    model->close_trace();
    throw;
  }
  model->close_trace();

  for (std::size_t i = 0; i < r.framebuffer.size(); i += 4) {
    std::uint32_t v;
    std::memcpy(&v, r.framebuffer.data() + i, 4);
    memory_->store32(spec::memory::kDeviceFramebufferBase + static_cast<std::uint32_t>(i), v);
  }

  functional::ShaderStats sh;
  sh.retired = r.retired;
  sh.chunk_issues = r.chunk_issues;
  sh.lanes_issued = r.chunk_issues * static_cast<std::uint64_t>(config_.chunk_size);
  sh.pixels = pixels();
  sh.closest_rays = r.closest_rays;
  sh.any_rays = r.any_rays;
  for (const streams::RayUnitCounters& u : r.counters.ray_units) {
    sh.nodes += u.nodes;
    sh.leaves += u.leaves;
    sh.tests += u.tests;
  }
  cycle::CycleStats launch_stats = cycle_stats(r);
  launch_stats.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (continues_frame()) {
    frame_ += launch_stats;
    stats_.shader += sh;
    lockstep_steps_ += r.lockstep_steps;
  } else {
    frame_ = std::move(launch_stats);
    stats_.shader = sh;
    lockstep_steps_ = r.lockstep_steps;
  }
  stats_.host_threads = 1;
  stats_.host_seconds = frame_.host_seconds;
  stats_.report = cycle::report(frame_, stats_.shader);
  if (options_.lockstep) stats_.report.group("lockstep").set("steps_compared", lockstep_steps_);

  if (r.fault) throw_fault(*r.fault);
}

void RtlDevice::throw_fault(const ChipFault& f) const {
  // The faulting pixel's block of lanes (functional::PixelMap).
  std::vector<functional::ShaderCore::Lane> lanes;
  pixel_map().lanes(f.pixel / static_cast<std::uint64_t>(config_.chunk_size), lanes);
  functional::DeviceMemory memory(image_, std::vector<std::uint8_t>(memory_->launch_block().begin(),
                                                                    memory_->launch_block().end()),
                                  firmware_.data, static_cast<std::uint32_t>(pixels()));
  const functional::Tracer tracer(image_, layout_, format_, config_.stack_depth);
  functional::ShaderCore core(firmware_, memory, tracer, format_, core_config(options_.watchdog));
  functional::ShaderStats stats;
  try {
    core.run_chunk(lanes, stats);
  } catch (const functional::ShaderFault& golden) {
    if (golden.pixel() == f.pixel && static_cast<std::uint32_t>(golden.kind()) == f.kind && golden.pc() == f.pc &&
        golden.address() == f.address) {
      throw golden;
    }
    throw Error(fmt::format("the RTL reports a fault of kind {} at pc {} address {:#010x} for pixel {}; the "
                            "functional model: {}",
                            f.kind, f.pc, f.address, f.pixel, golden.what()));
  }
  throw Error(fmt::format("the RTL reports a fault of kind {} at pc {} address {:#010x} for pixel {}; the functional "
                          "model runs that pixel's chunk without one",
                          f.kind, f.pc, f.address, f.pixel));
}

}  // namespace

std::string rtl_models_built() {
  std::string s;
  for (const ModelInfo& m : models<harness::Chip>()) {
    s += fmt::format("{}{}/{}", s.empty() ? "" : ", ", m.fact("config"), m.fact("isect"));
  }
  return s.empty() ? "none" : s;
}

void check_rtl_runs(const spec::HardwareConfig& config, fp::Format format, IsectMode isect) {
  // The RTL is built for the named configurations as spec/configs.toml has them.
  const spec::HardwareConfig* named = nullptr;
  for (const spec::HardwareConfig& c : spec::kConfigs) {
    if (c.name == config.name) named = &c;
  }
  if (!named || config::entries(*named) != config::entries(config)) {
    throw Error(fmt::format("the rtl backend runs the named configurations as spec/configs.toml has them (the RTL's "
                            "parameters are fixed when it is built: {}); this configuration ('{}') is not one of them "
                            "or was changed with --set or a file",
                            rtl_models_built(), config.name));
  }
  if (config.tu_slots != 1 && !config.tu_pipe) {
    throw Error(fmt::format("the rtl backend's chip has walker ray units of one slot or pipelined ones; configuration "
                            "'{}' has tu_slots = {} walkers (its ray units are co-simulated alone by tu_cosim --slots; "
                            "the cycle backend models the chip)",
                            config.name, config.tu_slots));
  }
  if (format != fp::format_by_name(std::string(config.format))) {
    throw Error(fmt::format("the rtl backend's chip of configuration '{}' computes in {}, not {}", config.name,
                            config.format, format.name()));
  }
  chip_model(config.name, isect);
}

std::unique_ptr<device::Device> make_rtl_device(const spec::HardwareConfig& config, fp::Format format,
                                                const RtlOptions& options) {
  check_rtl_runs(config, format, options.isect);
  return std::make_unique<RtlDevice>(config, format, options);
}

}  // namespace rpu::sim
