// The cycle backend: the functional core computes, this model times (docs/cycle-model.md).
// The device wires the chip's components (shader cores, ray dispatch, traversal units,
// caches and DRAM, timeline) and runs the event loop (cycle/event_queue.hpp) that wakes
// each at the cycle its next step can happen.
#include "cycle/cycle_device.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "cycle/core_timing.hpp"
#include "cycle/dispatch.hpp"
#include "cycle/event_queue.hpp"
#include "cycle/speed_of_light.hpp"
#include "cycle/tu_pipe_timing.hpp"
#include "cycle/walker_timing.hpp"
#include "device/device_base.hpp"
#include "fp/fast32.hpp"
#include "functional/tracer.hpp"

namespace rpu::cycle {

namespace {

// The chip's ray units read through the node and triangle caches.
class CacheLines final : public LineSource {
 public:
  CacheLines(Cache& nodes, Cache& triangles) : nodes_(nodes), triangles_(triangles) {}
  Cycle read(Cycle now, std::uint32_t address, std::uint32_t bytes, bool node) override {
    return (node ? nodes_ : triangles_).read(now, address, bytes);
  }

 private:
  Cache& nodes_;
  Cache& triangles_;
};

class CycleDevice final : public device::DeviceBase, CoreTiming::Chip, RayUnitTiming::Ports {
 public:
  CycleDevice(const spec::HardwareConfig& config, fp::Format format, const CycleOptions& options)
      : DeviceBase(config, format),
        options_(options),
        timeline_(options.timeline_begin, options.timeline_end, options.timeline_max_slices, options.timeline) {}
  ~CycleDevice() override { end_frame(); }

  std::string_view backend() const override { return "cycle"; }

 private:
  void run(const ProgressCallback& progress) override;
  void start_launch(const ProgressCallback& progress);
  void make_memory();
  void make_ray_units();
  // The event loop: the cores are agents 0 .. cores-1, the ray units the next.
  void run_events();
  void wake_unit(std::size_t u, Cycle at) { events_->wake(static_cast<std::uint32_t>(cores_.size() + u), at); }
  // The fault the launch ends with, if any; rpu::Error if a chunk was left live.
  const functional::ShaderFault* launch_fault(Cycle now) const;
  void finish(Cycle end);
  void add_to_frame();

  // The shader cores' links (CoreTiming::Chip).
  void queue_ray(Ray ray, Cycle at) override;
  std::size_t queued_rays(std::uint32_t core) const override { return dispatch_->waiting(core); }
  void round_lanes(std::uint64_t round, std::uint64_t chunk,
                   std::vector<functional::ShaderCore::Lane>& lanes) const override {
    lanes_of(round, chunk, lanes);
  }
  void round_done() override;
  std::uint32_t first_fault() const override { return fault_pixel_; }
  void fault(std::uint32_t pixel) override;
  void halted(std::uint32_t pixel, Cycle cycles) override {
    out_.pixel_cycles[pixel] = static_cast<std::uint32_t>(cycles);
  }
  // The ray units' ports (RayUnitTiming::Ports).
  std::optional<Ray> next_ray(Cycle from) override;
  std::optional<Ray> send_ray(Cycle now, std::size_t unit) override;
  bool rays_waiting() const override { return dispatch_->any_waiting(); }
  void answer(Ray& ray, Cycle now) override;

  CycleOptions options_;

  // One launch's chip (start_launch() sets it up).
  std::optional<functional::Tracer> tracer_;
  std::optional<functional::ShaderCore> shader_;
  functional::ShaderStats shader_stats_;
  std::optional<Dram> dram_;
  // Pair p of node and triangle caches at p; ray unit u reads through pair
  // u / (traversal_units / ray_caches). Reserved, never grown: lines_ refers into them.
  std::vector<Cache> node_caches_, triangle_caches_;
  std::vector<CacheLines> lines_;
  std::optional<EventQueue> events_;
  std::optional<RayDispatch> dispatch_;
  std::vector<CoreTiming> cores_;
  // Walkers, or pipelined units: traversal unit u's walkers at u * walkers_ ...
  std::vector<std::unique_ptr<RayUnitTiming>> units_;
  std::vector<Cycle> unit_ran_;  // the cycle each unit last ran in
  // The ray the dispatch sent in cycle sent_in_, until its unit collects it.
  Cycle sent_in_ = kNever;
  std::optional<RayDispatch::Sent> sent_;
  std::vector<bool> takes_;  // per unit: takes a ray in cycle sent_in_
  std::uint32_t walkers_ = 1;  // per traversal unit
  std::vector<IuTimer> ius_;
  std::uint64_t rounds_done_ = 0, rounds_total_ = 0;
  const ProgressCallback* progress_ = nullptr;
  std::uint32_t fault_pixel_ = CoreTiming::kNoFault;
  Timeline timeline_;
  CycleStats out_;    // this launch's
  CycleStats frame_;  // the frame's: a selected frame's two launches added
};

// The ray waits in its core's queue until a traversal unit takes it. The units are
// offered it in turn, then their next walkers: units fill evenly.
void CycleDevice::queue_ray(Ray ray, Cycle at) {
  dispatch_->queue(std::move(ray), at);
  const auto tus = static_cast<std::size_t>(config_.traversal_units);
  for (std::size_t k = 0; k < units_.size(); ++k) {
    const std::size_t u = (k % tus) * walkers_ + k / tus;
    wake_unit(u, units_[u]->ray_waiting(at));
  }
}

void CycleDevice::answer(Ray& ray, Cycle now) {
  RayLatency& latency = ray.log.mode == functional::TraceMode::kAny ? out_.any_latency : out_.closest_latency;
  ++latency.rays;
  latency.waiting += ray.taken - ray.arrived;
  latency.in_unit += now - ray.taken;
  cores_[ray.core].ray_answered(ray, now);
}

void CycleDevice::round_done() {
  ++rounds_done_;
  if (*progress_) (*progress_)(rounds_done_, rounds_total_);
}

void CycleDevice::fault(std::uint32_t pixel) {
  fault_pixel_ = pixel;
  for (CoreTiming& core : cores_) core.forget_ready_times();
}

std::optional<Ray> CycleDevice::next_ray(Cycle from) {
  std::optional<Ray> ray = dispatch_->next();
  if (ray) cores_[ray->core].ray_dispatched(from);
  return ray;
}

// The cycle's ray and its unit are chosen when the first unit that takes a ray runs in
// it, from every unit's state at the cycle's start, as rpu_ray_dispatch chooses them: a
// unit that ran earlier in the cycle took no ray (it would have asked), one that has
// not run yet has not changed. The unit chosen runs later in the cycle (every unit runs
// while rays wait) and collects it.
std::optional<Ray> CycleDevice::send_ray(Cycle now, std::size_t unit) {
  if (sent_in_ != now) {
    if (sent_) {
      throw Error(fmt::format("cycle model: the ray sent to traversal unit {} in cycle {} was not taken",
                              sent_->unit, sent_in_));
    }
    sent_in_ = now;
    for (std::size_t u = 0; u < units_.size(); ++u) takes_[u] = u == unit || (unit_ran_[u] != now && units_[u]->takes_ray());
    sent_ = dispatch_->send(now, takes_);
    if (sent_) cores_[sent_->ray.core].ray_dispatched(now);
  }
  if (!sent_ || sent_->unit != unit) return std::nullopt;
  std::optional<Ray> ray = std::move(sent_->ray);
  sent_.reset();
  return ray;
}

// The traversal units: `tu_slots` walkers each, or a pipelined unit each (tu_pipe).
void CycleDevice::make_ray_units() {
  ius_.assign(static_cast<std::size_t>(config_.intersection_units), IuTimer{});
  units_.clear();
  unit_ran_.assign(static_cast<std::size_t>(config_.traversal_units) * walkers_, kNever);
  takes_.assign(unit_ran_.size(), false);
  sent_in_ = kNever;
  sent_.reset();
  RayUnitTiming::Ports& ports = *this;
  const auto tus = static_cast<std::size_t>(config_.traversal_units);
  for (std::size_t u = 0; u < tus; ++u) {
    // Traversal unit u sends its tests to its own share of the IUs, as a ray unit pairs
    // a TU with its IU (rpu_ray_unit): IUs [u I / T, (u + 1) I / T), or with fewer IUs
    // than TUs the one it shares.
    const std::size_t first = u * ius_.size() / tus;
    const std::span<IuTimer> ius(ius_.data() + first, std::max(first + 1, (u + 1) * ius_.size() / tus) - first);
    CacheLines& lines = lines_[u / (tus / lines_.size())];
    if (config_.tu_pipe) {
      units_.push_back(std::make_unique<PipeUnitTiming>(PipeCosts::of(config_, layout_.isect_mode), lines, ius, ports,
                                                        u, &*tracer_));
      continue;
    }
    for (std::uint32_t s = 0; s < walkers_; ++s) {
      std::string track = walkers_ == 1 ? fmt::format("TU {}", u) : fmt::format("TU {} slot {}", u, s);
      units_.push_back(std::make_unique<WalkerTiming>(WalkCosts::of(config_, layout_.isect_mode), lines, ius, ports,
                                                      timeline_, std::move(track)));
    }
  }
}

// The ray units' node and triangle caches, `ray_caches` pairs, and the DRAM behind
// every cache.
void CycleDevice::make_memory() {
  dram_.emplace(config_.dram);
  const auto line_wait = static_cast<Cycle>(config_.latency.line_wait);
  const auto pairs = static_cast<std::size_t>(config_.ray_caches);
  node_caches_.clear();
  triangle_caches_.clear();
  lines_.clear();
  node_caches_.reserve(pairs);
  triangle_caches_.reserve(pairs);
  lines_.reserve(pairs);
  for (std::size_t p = 0; p < pairs; ++p) {
    node_caches_.emplace_back(config_.node_cache, *dram_, line_wait);
    triangle_caches_.emplace_back(config_.triangle_cache, *dram_, line_wait);
    lines_.emplace_back(node_caches_.back(), triangle_caches_.back());
  }
}

// The chip of one launch, its cores started on their first pixels.
void CycleDevice::start_launch(const ProgressCallback& progress) {
  tracer_.emplace(image_, layout_, format_, config_.stack_depth);
  shader_.emplace(firmware_, *memory_, *tracer_, format_, core_config(options_.watchdog));
  shader_stats_ = {};
  make_memory();
  fault_pixel_ = CoreTiming::kNoFault;
  // Pass 1 of a selected frame starts where pass 0 ended.
  timeline_.start(continues_frame() ? frame_.cycles : 0, continues_frame() ? frame_.timeline_slices : 0);
  out_ = {};
  out_.config = std::string(config_.name);
  out_.clock_mhz = config_.clock_mhz;
  out_.width = launch_.width;
  out_.height = launch_.height;
  out_.pixel_cycles.assign(pixels(), 0);
  out_.dram_bytes_per_cycle = config_.dram.bytes_per_cycle;
  progress_ = &progress;
  rounds_done_ = 0;
  rounds_total_ = (pixels() + static_cast<std::uint64_t>(config_.chunk_size) - 1) /
                  static_cast<std::uint64_t>(config_.chunk_size);
  const auto cores = static_cast<std::uint32_t>(config_.shader_cores);
  walkers_ = config_.tu_pipe ? 1 : static_cast<std::uint32_t>(config_.tu_slots);
  events_.emplace(cores + static_cast<std::size_t>(config_.traversal_units) * walkers_);
  dispatch_.emplace(cores, config_.tu_packet > 1);
  cores_.clear();
  cores_.reserve(cores);
  CoreTiming::Chip& chip = *this;
  for (std::uint32_t c = 0; c < cores; ++c) {
    cores_.emplace_back(c, config_, *shader_, shader_stats_, *dram_, *events_, timeline_, chip);
    cores_.back().start();
  }
  make_ray_units();
}

void CycleDevice::run_events() {
  // One flush-to-zero scope for the frame's fp32 fast path, not one per step.
  const fp::fast32::FlushScope flush;
  const auto cores = static_cast<std::uint32_t>(cores_.size());
  while (const std::optional<EventQueue::Wakeup> e = events_->next()) {
    if (e->agent < cores) {
      cores_[e->agent].run(e->at);
    } else {
      unit_ran_[e->agent - cores] = e->at;
      wake_unit(e->agent - cores, units_[e->agent - cores]->advance(e->at));
    }
  }
}

const functional::ShaderFault* CycleDevice::launch_fault(Cycle now) const {
  for (const CoreTiming& core : cores_) {
    if (const functional::ShaderFault* f = core.fault_at(fault_pixel_)) return f;
  }
  for (const CoreTiming& core : cores_) {
    if (const std::optional<std::uint64_t> chunk = core.live_chunk()) {
      throw Error(fmt::format("cycle model: no event left at cycle {} while chunk {} is live", now, *chunk));
    }
  }
  return nullptr;
}

void CycleDevice::run(const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  start_launch(progress);
  run_events();
  const Cycle now = events_->now();
  const functional::ShaderFault* faulted = launch_fault(now);
  finish(now + 1);
  out_.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  add_to_frame();
  if (faulted) {
    const functional::ShaderFault fault = *faulted;
    tracer_.reset();
    shader_.reset();
    throw fault;
  }
  tracer_.reset();
  shader_.reset();
}

// The launch's statistics become the frame's, or join pass 0's (a selected frame).
void CycleDevice::add_to_frame() {
  if (continues_frame()) {
    frame_ += out_;
    stats_.shader += shader_stats_;
  } else {
    frame_ = out_;
    stats_.shader = shader_stats_;
  }
  stats_.host_threads = 1;
  stats_.host_seconds = frame_.host_seconds;
  stats_.report = report(frame_, stats_.shader);
  if (options_.frame_stats) options_.frame_stats(frame_);
}

// The launch's totals, times and bounds; it ended at `end`.
void CycleDevice::finish(Cycle end) {
  timeline_.flush();
  out_.timeline_slices = timeline_.slices();
  out_.timeline_cut_at = timeline_.cut_at();
  // The last lanes to enter a pipeline may do so after the last event.
  for (const CoreTiming& core : cores_) end = std::max(end, core.accounted());
  // Then write-back data caches write their dirty lines, all at once (rpu_top's done_o
  // waits for them).
  Cycle flushed = end;
  for (CoreTiming& core : cores_) flushed = std::max(flushed, core.flush_data_cache(end));
  end = flushed;
  out_.cycles = end;
  for (CoreTiming& core : cores_) {
    out_.cores.push_back(core.finish(end));
    out_.data_cache += core.data_cache_stats();
  }
  // A unit's times are its slots' summed: they add up to cycles x slots.
  out_.tu_slots = static_cast<std::uint32_t>(config_.tu_slots);
  out_.tus.assign(static_cast<std::size_t>(config_.traversal_units), TraversalUnitTime{});
  for (std::size_t u = 0; u < units_.size(); ++u) out_.tus[u / walkers_] += units_[u]->time(end);
  for (const IuTimer& iu : ius_) out_.ius.push_back(iu.time);
  for (std::size_t p = 0; p < node_caches_.size(); ++p) {
    out_.add_ray_caches(node_caches_[p].stats(), triangle_caches_[p].stats());
  }
  out_.dram = dram_->stats();
  out_.closest_rays = shader_stats_.closest_rays;
  out_.any_rays = shader_stats_.any_rays;
  out_.thread_instructions = shader_stats_.instructions();

  out_.bounds = speed_of_light(out_, config_, layout_.isect_mode);
}

}  // namespace

std::unique_ptr<device::Device> make_cycle_device(const spec::HardwareConfig& config, fp::Format format,
                                                  const CycleOptions& options) {
  return std::make_unique<CycleDevice>(config, format, options);
}

}  // namespace rpu::cycle
