// The backends of this build and what each adds to the command line.
#include "device/registry.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/error.hpp"
#include "common/whole_number.hpp"
#include "cycle/cycle_device.hpp"
#include "image/image.hpp"
#ifdef RPU_HAVE_RTL
#include "rtl_device.hpp"
#endif

namespace rpu::device {

void Backend::add_options(CLI::App&) {}
void Backend::check(const RenderSettings&, std::string_view) const {}
void Backend::check_runs(const spec::HardwareConfig&, fp::Format, IsectMode) const {}
std::vector<BackendOutput> Backend::outputs() const { return {}; }
void Backend::finish(const DeviceStats&) {}

namespace {

// A cycle window [BEGIN, END) of a backend's recording: two whole numbers below 2^64
// (CLI11 alone turns 2^64 into 2^64 - 1 without a word), read only with its recording.
CLI::Option* add_window_option(CLI::App& command, const std::string& name, std::vector<std::uint64_t>& window,
                               const std::string& help) {
  return command.add_option(name, window, help)->expected(2)->check(whole_number(name, 0));
}

void check_window(const std::string& name, const std::vector<std::uint64_t>& window, const std::string& recording,
                  bool recorded, bool given) {
  if (given && !recorded) {
    throw Error(fmt::format("{} needs {}: it chooses the cycles {} records", name, recording, recording));
  }
  if (window[0] >= window[1]) throw Error(fmt::format("{} {} {}: the window is empty", name, window[0], window[1]));
}

// A window that begins after the frame's last cycle recorded nothing.
void warn_past_the_end(const std::string& name, const std::vector<std::uint64_t>& window, const std::string& file,
                       const StatsTree& report) {
  const StatsTree* cycles = report.find("cycles");
  if (cycles == nullptr) return;
  const std::uint64_t* last = std::get_if<std::uint64_t>(&cycles->value());
  if (last != nullptr && window[0] >= *last) {
    fmt::print(stderr, "rpu: warning: {} {} {}: the frame ended at cycle {}, so {} holds no cycles\n", name, window[0],
               window[1], *last, file);
  }
}

// The golden model (functional_device.cpp); --pixel traces one pixel's instructions.
class FunctionalBackend final : public Backend {
 public:
  std::string_view name() const override { return "functional"; }
  void add_options(CLI::App& command) override {
    command
        .add_option("--pixel", pixel_,
                    "functional backend: print every instruction pixel X,Y retires on stdout, with its source line and "
                    "the register it writes (docs/shaders.md \"Debugging\")")
        ->type_name("X,Y")
        ->delimiter(',')
        ->expected(2);
  }
  void check(const RenderSettings& settings, std::string_view) const override {
    if (pixel_.empty()) return;
    if (pixel_[0] >= static_cast<std::uint64_t>(settings.width) || pixel_[1] >= static_cast<std::uint64_t>(settings.height)) {
      throw Error(fmt::format("--pixel {},{}: outside the {}x{} image", pixel_[0], pixel_[1], settings.width,
                              settings.height));
    }
    width_ = static_cast<std::uint32_t>(settings.width);
  }
  std::unique_ptr<Device> make(const spec::HardwareConfig& config, fp::Format format,
                               const DeviceOptions& options) override {
    FunctionalOptions o;
    o.host_threads = options.host_threads;
    o.watchdog = options.watchdog;
    if (!pixel_.empty()) {
      o.trace_pixel = static_cast<std::uint32_t>(pixel_[1]) * width_ + static_cast<std::uint32_t>(pixel_[0]);
      o.trace = [](const std::string& line) { fmt::print("{}\n", line); };
    }
    return make_functional_device(config, format, o);
  }

 private:
  std::vector<std::uint64_t> pixel_;
  mutable std::uint32_t width_ = 0;  // the image's, from check()
};

// The per-pixel cycle cost: false colour over [0, max] in a PNG, the cycles themselves
// in an EXR.
void write_cycle_heatmap(const cycle::CycleStats& st, const std::filesystem::path& file) {
  Image image(st.width, st.height);
  const std::uint32_t max = std::max<std::uint32_t>(
      1, st.pixel_cycles.empty() ? 1 : *std::max_element(st.pixel_cycles.begin(), st.pixel_cycles.end()));
  const bool linear = file.extension() == ".exr";
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const double c = st.pixel_cycles[i];
    image.pixels[i] = linear ? glm::vec3(static_cast<float>(c)) : false_colour(c / max);
  }
  write_image(image, file);
}

// The cycle model (docs/cycle-model.md): its heatmap and timeline.
class CycleBackend final : public Backend {
 public:
  std::string_view name() const override { return "cycle"; }

  void add_options(CLI::App& command) override {
    command.add_option("--heatmap", heatmap_,
                       "cycle backend: per-pixel cycle cost, .png (false colour) and/or .exr (cycles, linear)");
    command.add_option("--trace", trace_,
                       "cycle backend: timeline of the units in Chrome/Perfetto trace JSON (1 us shown = 1 cycle)");
    window_option_ = add_window_option(command, "--trace-window", window_,
                                       "cycle backend: the timeline's cycles [BEGIN, END)");
    window_option_->capture_default_str();
  }

  void check(const RenderSettings&, std::string_view) const override {
    check_window("--trace-window", window_, "--trace", !trace_.empty(), window_option_->count() != 0);
  }

  std::vector<BackendOutput> outputs() const override {
    std::vector<BackendOutput> out;
    for (const std::filesystem::path& f : heatmap_) out.push_back({"--heatmap", f, {".png", ".exr"}});
    if (!trace_.empty()) out.push_back({"--trace", trace_, {".json"}});
    return out;
  }

  std::unique_ptr<Device> make(const spec::HardwareConfig& config, fp::Format format,
                               const DeviceOptions& options) override {
    cycle::CycleOptions o;
    o.watchdog = options.watchdog;
    // The heatmap and the timeline's metadata come from the frame's typed statistics.
    if (!heatmap_.empty() || !trace_.empty()) o.frame_stats = [this](const cycle::CycleStats& s) { frame_ = s; };
    if (!trace_.empty()) {
      o.timeline_begin = window_[0];
      o.timeline_end = window_[1];
      timeline_.emplace(trace_);
      o.timeline = [this](const cycle::TimelineSlice& s) { timeline_->add(s); };
    }
    return cycle::make_cycle_device(config, format, o);
  }

  void finish(const DeviceStats& stats) override {
    fmt::print(stderr, "{}", cycle::summarize(stats.report));
    for (const std::filesystem::path& f : heatmap_) write_cycle_heatmap(frame_.value(), f);
    if (!timeline_) return;
    warn_past_the_end("--trace-window", window_, trace_.string(), stats.report);
    timeline_->finish(frame_.value());
    if (frame_->timeline_cut_at) {
      fmt::print(stderr, "rpu: warning: --trace {}: {}; start --trace-window at {} to see the rest\n", trace_.string(),
                 cycle::timeline_cut_reason(*frame_), *frame_->timeline_cut_at);
    }
  }

 private:
  std::vector<std::filesystem::path> heatmap_;  // .png false colour / .exr linear cycles
  std::filesystem::path trace_;                 // Chrome trace JSON
  std::vector<std::uint64_t> window_{0, 200'000};
  CLI::Option* window_option_ = nullptr;
  std::optional<cycle::TimelineWriter> timeline_;
  std::optional<cycle::CycleStats> frame_;
};

#ifdef RPU_HAVE_RTL
// The Verilated chip (sim/rtl_device.hpp, docs/chip.md): its waveforms and lockstep.
class RtlBackend final : public Backend {
 public:
  std::string_view name() const override { return "rtl"; }

  void add_options(CLI::App& command) override {
    command.add_option("--waves", waves_, "rtl backend: FST waveforms of the chip (GTKWave, Surfer)");
    window_option_ = add_window_option(command, "--wave-window", window_,
                                       "rtl backend: the waveforms' cycles [BEGIN, END)");
    command.add_flag("--lockstep", lockstep_,
                     "rtl backend: compare every core with the functional model, instruction by instruction");
  }

  void check(const RenderSettings& settings, std::string_view select) const override {
    check_window("--wave-window", window_, "--waves", !waves_.empty(), window_option_->count() != 0);
    if (!waves_.empty() && settings.select.enabled()) {
      throw Error(fmt::format("--waves records one launch and --select {} renders the frame in two; record "
                              "without --select",
                              select));
    }
  }

  void check_runs(const spec::HardwareConfig& config, fp::Format format, IsectMode isect) const override {
    sim::check_rtl_runs(config, format, isect);
  }

  std::vector<BackendOutput> outputs() const override {
    if (waves_.empty()) return {};
    return {{"--waves", waves_, {".fst"}}};
  }

  std::unique_ptr<Device> make(const spec::HardwareConfig& config, fp::Format format,
                               const DeviceOptions& options) override {
    sim::RtlOptions o;
    o.watchdog = options.watchdog;
    o.isect = options.isect;
    o.lockstep = lockstep_;
    o.waves = waves_.string();
    o.wave_begin = window_[0];
    o.wave_end = window_[1];
    return sim::make_rtl_device(config, format, o);
  }

  void finish(const DeviceStats& stats) override {
    fmt::print(stderr, "{}", cycle::summarize(stats.report));
    if (!waves_.empty()) warn_past_the_end("--wave-window", window_, waves_.string(), stats.report);
  }

 private:
  std::filesystem::path waves_;  // FST
  std::vector<std::uint64_t> window_{0, ~std::uint64_t{0}};
  CLI::Option* window_option_ = nullptr;
  bool lockstep_ = false;
};
#endif

}  // namespace

Registry::Registry() {
  entries_.push_back({std::make_unique<FunctionalBackend>(), {}});
  entries_.push_back({std::make_unique<CycleBackend>(), {}});
#ifdef RPU_HAVE_RTL
  entries_.push_back({std::make_unique<RtlBackend>(), {}});
#endif
}

std::vector<std::string> Registry::names() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.emplace_back(e.backend->name());
  return out;
}

Backend* Registry::find(std::string_view name) const {
  for (const Entry& e : entries_) {
    if (e.backend->name() == name) return e.backend.get();
  }
  return nullptr;
}

void Registry::add_options(CLI::App& command) {
  for (Entry& e : entries_) {
    const std::size_t before = command.get_options().size();
    e.backend->add_options(command);
    const std::vector<CLI::Option*> all = command.get_options();
    e.options.assign(all.begin() + static_cast<std::ptrdiff_t>(before), all.end());
  }
}

void Registry::refuse_others(std::string_view chosen) const {
  for (const Entry& e : entries_) {
    if (e.backend->name() == chosen) continue;
    std::vector<std::string> given;
    for (const CLI::Option* o : e.options) {
      if (o->count() != 0) given.push_back(o->get_name());
    }
    if (given.empty()) continue;
    const std::string last = given.back();
    given.pop_back();
    throw Error(fmt::format("{}{}{} {} --backend {}", fmt::join(given, ", "), given.empty() ? "" : " and ", last,
                            given.empty() ? "needs" : "need", e.backend->name()));
  }
}

std::unique_ptr<Device> make_device(std::string_view name, const spec::HardwareConfig& config, fp::Format format,
                                    const DeviceOptions& options) {
  const Registry registry;
  Backend* backend = registry.find(name);
  if (!backend) {
    throw Error(fmt::format("no device backend '{}' in this build (it has {})", name, fmt::join(registry.names(), ", ")));
  }
  return backend->make(config, format, options);
}

}  // namespace rpu::device
