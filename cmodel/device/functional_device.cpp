// The functional backend: the golden model of the whole chip. Pixels go to device
// threads in a fixed pattern, chunks of threads run on host threads in any order, and
// since threads share nothing writable, the image is the same for every host thread
// count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "common/error.hpp"
#include "device/device_base.hpp"
#include "functional/tracer.hpp"

namespace rpu::device {

namespace {

class FunctionalDevice final : public DeviceBase {
 public:
  FunctionalDevice(const spec::HardwareConfig& config, fp::Format format, const FunctionalOptions& options)
      : DeviceBase(config, format), options_(options) {}

  std::string_view backend() const override { return "functional"; }

 private:
  void run(const ProgressCallback& progress) override {
    const auto start = std::chrono::steady_clock::now();
    const functional::Tracer tracer(image_, layout_, format_, config_.stack_depth, options_.fast_path);
    const functional::ShaderCoreConfig core_config = DeviceBase::core_config(options_.watchdog);

    // One work item is one chunk of one round.
    const auto chunk = static_cast<std::uint64_t>(config_.chunk_size);
    const std::uint64_t chunks_per_round = device_threads() / chunk;
    const std::uint64_t items = (pixels() + chunk - 1) / chunk;

    std::atomic<std::uint64_t> next{0}, done{0};
    std::atomic<std::uint64_t> first_fault_item{std::numeric_limits<std::uint64_t>::max()};
    std::mutex mutex;
    std::optional<std::string> fault;
    std::uint64_t fault_item = std::numeric_limits<std::uint64_t>::max();
    functional::ShaderStats total;

    const auto worker = [&] {
      functional::ShaderCore core(firmware_, *memory_, tracer, format_, core_config, options_.fast_path);
      functional::ShaderStats stats;
      std::vector<functional::ShaderCore::Lane> lanes;
      for (std::uint64_t item; (item = next.fetch_add(1)) < items;) {
        // After a fault, only items before it still run, so that the fault reported is
        // the first in pixel order whatever the host threads' timing.
        if (item > first_fault_item.load()) break;
        lanes_of(item / chunks_per_round, item % chunks_per_round, lanes);
        try {
          core.run_chunk(lanes, stats);
        } catch (const Error& e) {
          const std::lock_guard lock(mutex);
          if (item < fault_item) {
            fault_item = item;
            fault = e.what();
            first_fault_item = item;
          }
        }
        if (progress) progress(done.fetch_add(1) + 1, items);
      }
      const std::lock_guard lock(mutex);
      total += stats;
    };
    const int n = options_.host_threads > 0 ? options_.host_threads
                                             : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    {
      std::vector<std::jthread> pool;
      for (int i = 1; i < n; ++i) pool.emplace_back(worker);
      worker();
    }
    stats_.shader = total;
    stats_.host_threads = n;
    stats_.host_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (fault) throw Error(*fault);
  }

  FunctionalOptions options_;
};

}  // namespace

std::unique_ptr<Device> make_functional_device(const spec::HardwareConfig& config, fp::Format format,
                                               const FunctionalOptions& options) {
  return std::make_unique<FunctionalDevice>(config, format, options);
}

}  // namespace rpu::device
