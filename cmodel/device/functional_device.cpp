// The functional backend: the golden model of the whole chip. Pixels go to device
// threads in a fixed pattern, chunks of threads run on host threads in any order, and
// since threads share nothing writable, the image is the same for every host thread
// count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "common/error.hpp"
#include "common/host_threads.hpp"
#include "device/device_base.hpp"
#include "functional/tracer.hpp"

namespace rpu::device {

namespace {

// What the shader cores did, under the names the cycle backend's report gives the same
// counts (cycle::report); the functional backend has no timing.
StatsTree report(const functional::ShaderStats& s, double host_seconds, int host_threads) {
  StatsTree r;
  r.set("host_seconds", host_seconds).set("host_threads", host_threads).set("pixels", s.pixels);
  StatsTree& rays = r.group("rays");
  rays.set("closest", s.closest_rays).set("any", s.any_rays).set("total", s.closest_rays + s.any_rays);
  if (s.self_hits_counted) rays.set("self_hits", s.self_hits);
  StatsTree& instructions = r.group("instructions");
  instructions.set("thread", s.instructions()).set("chunk_issues", s.chunk_issues);
  instructions.set("simd_efficiency", s.lanes_issued ? static_cast<double>(s.instructions()) /
                                                           static_cast<double>(s.lanes_issued)
                                                     : 0.0);
  StatsTree& by_class = instructions.group("by_class");
  for (std::size_t k = 0; k < spec::isa::kClassNames.size(); ++k) by_class.set(spec::isa::kClassNames[k], s.retired[k]);
  r.group("traversal").set("nodes", s.nodes).set("leaves", s.leaves).set("tests", s.tests);
  return r;
}

class FunctionalDevice final : public DeviceBase {
 public:
  FunctionalDevice(const spec::HardwareConfig& config, fp::Format format, const FunctionalOptions& options)
      : DeviceBase(config, format), options_(options) {}
  ~FunctionalDevice() override { end_frame(); }

  std::string_view backend() const override { return "functional"; }

 private:
  void run(const ProgressCallback& progress) override {
    const auto start = std::chrono::steady_clock::now();
    const functional::Tracer tracer(image_, layout_, format_, config_.stack_depth, options_.fast_path);
    const functional::ShaderCoreConfig core_config = DeviceBase::core_config(options_.watchdog);

    // One work item is one block of pixels, a chunk's work for a round: items in pixel
    // order.
    const functional::PixelMap map = pixel_map();
    const std::uint64_t items = map.blocks();

    std::atomic<std::uint64_t> next{0}, done{0};
    // The first error in item order, of any kind, is what one host thread would meet.
    // Its key is the item + 1; making the core comes before every item (key 0).
    std::atomic<std::uint64_t> error_key{std::numeric_limits<std::uint64_t>::max()};
    std::mutex mutex;
    std::exception_ptr error;
    functional::ShaderStats total;
    const auto keep = [&](std::uint64_t key) {
      const std::lock_guard lock(mutex);
      if (key < error_key.load()) {
        error = std::current_exception();
        error_key = key;
      }
    };

    // Runs on every host thread; its errors are kept by item, so that the one reported is
    // the first pixel's whatever the threads' timing.
    const auto worker = [&] {
      try {
        functional::ShaderCore core(firmware_, *memory_, tracer, format_, core_config, options_.fast_path);
        functional::ShaderStats stats;
        std::vector<functional::ShaderCore::Lane> lanes;
        for (std::uint64_t item; (item = next.fetch_add(1)) < items;) {
          // After an error only items before it still run, so that the one reported
          // is the first in pixel order whatever the host threads' timing.
          if (item + 1 > error_key.load()) break;
          map.lanes(item, lanes);
          try {
            const auto traced = std::find_if(lanes.begin(), lanes.end(), [&](const auto& l) {
              return options_.trace_pixel && l.pixel == *options_.trace_pixel;
            });
            if (traced == lanes.end()) {
              core.run_chunk(lanes, stats);
            } else {
              const auto lane = static_cast<std::size_t>(traced - lanes.begin());
              const functional::ShaderCore::StepObserver print = [&](const functional::StepRecord& r,
                                                                     const functional::ShaderCore::Chunk& c) {
                if (r.lanes >> lane & 1) options_.trace(core.trace_line(r, c.threads()[lane]));
              };
              core.run_chunk(lanes, stats, nullptr, &print);
            }
            if (progress) progress(done.fetch_add(1) + 1, items);
          } catch (...) {
            keep(item + 1);
          }
        }
        const std::lock_guard lock(mutex);
        total += stats;
      } catch (...) {
        keep(0);
      }
    };
    const int n = options_.host_threads > 0 ? options_.host_threads
                                             : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    run_host_threads(n, [&](int) { worker(); });
    double host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (continues_frame()) {
      total += stats_.shader;
      host_seconds += stats_.host_seconds;
    }
    stats_.shader = total;
    stats_.host_threads = n;
    stats_.host_seconds = host_seconds;
    stats_.report = report(total, host_seconds, n);
    if (error) std::rethrow_exception(error);
  }

  FunctionalOptions options_;
};

}  // namespace

std::unique_ptr<Device> make_functional_device(const spec::HardwareConfig& config, fp::Format format,
                                               const FunctionalOptions& options) {
  return std::make_unique<FunctionalDevice>(config, format, options);
}

}  // namespace rpu::device
