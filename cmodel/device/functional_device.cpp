// The functional backend: the golden model of the whole chip. Pixels go to device
// threads in a fixed pattern, chunks of threads run on host threads in any order, and
// since threads share nothing writable, the image is the same for every host thread
// count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "common/error.hpp"
#include "device/device.hpp"
#include "functional/device_memory.hpp"
#include "functional/shader_core.hpp"
#include "functional/tracer.hpp"
#include "memory/memory_image.hpp"

namespace rpu::device {

namespace mm = spec::memory;

namespace {

class FunctionalDevice final : public Device {
 public:
  FunctionalDevice(const spec::HardwareConfig& config, fp::Format format, const FunctionalOptions& options)
      : config_(config), format_(format), options_(options) {}
  ~FunctionalDevice() override {
    if (frame_.valid()) frame_.wait();
  }

  std::string_view backend() const override { return "functional"; }

  void load_image(std::vector<std::uint8_t> image, const std::string& source) override {
    idle();
    layout_ = validate_memory_image(image, source);
    image_ = std::move(image);
  }

  void load_firmware(isa::Firmware firmware, std::vector<std::string> shader_names) override {
    idle();
    std::vector<std::uint32_t> table;
    for (const std::string& name : shader_names) {
      const std::string label = "hit_" + name;
      const auto s = firmware.symbols.find(label);
      if (s == firmware.symbols.end() || s->second.kind != isa::Symbol::Kind::kCode) {
        throw Error(fmt::format("the firmware has no code label '{}' for the scene's shader '{}'", label, name));
      }
      table.push_back(s->second.value);
    }
    firmware_ = std::move(firmware);
    shader_table_ = std::move(table);
    has_firmware_ = true;
  }

  void launch(const Launch& launch, ProgressCallback progress) override {
    idle();
    if (image_.empty()) throw Error("launch before load_image");
    if (!has_firmware_) throw Error("launch before load_firmware");
    if (launch.width <= 0 || launch.height <= 0 || launch.spp <= 0 || launch.max_depth < 0) {
      throw Error(fmt::format("launch of {}x{} pixels, {} spp, max depth {}: sizes must be positive", launch.width,
                              launch.height, launch.spp, launch.max_depth));
    }
    const std::uint64_t pixels = std::uint64_t(launch.width) * std::uint64_t(launch.height);
    if (pixels * mm::kFramebufferBytesPerPixel > std::numeric_limits<std::uint32_t>::max() - mm::kDeviceFramebufferBase) {
      throw Error(fmt::format("a {}x{} framebuffer does not fit the device's address space", launch.width,
                              launch.height));
    }
    memory_.emplace(image_, make_launch_block(image_, layout_, launch, shader_table_), firmware_.data,
                    static_cast<std::uint32_t>(pixels));
    launch_ = launch;
    frame_ = std::async(std::launch::async, [this, progress] { run(progress); });
  }

  void wait() override {
    if (frame_.valid()) frame_.get();
  }

  std::vector<glm::vec4> read_framebuffer() const override {
    if (!memory_) throw Error("read_framebuffer before a launch");
    const std::span<const std::uint8_t> fb = memory_->framebuffer();
    std::vector<glm::vec4> out(fb.size() / sizeof(glm::vec4));
    std::memcpy(out.data(), fb.data(), out.size() * sizeof(glm::vec4));
    return out;
  }

  DeviceStats stats() const override { return stats_; }

 private:
  void idle() {
    if (frame_.valid()) frame_.get();
  }

  void run(const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    const functional::Tracer tracer(image_, layout_, format_, config_.stack_depth, options_.fast_path);
    functional::ShaderCoreConfig core_config;
    core_config.registers = config_.registers;
    core_config.chunk_size = config_.chunk_size;
    core_config.call_depth = config_.call_depth;
    core_config.stack_bytes = static_cast<std::uint32_t>(config_.stack_bytes);
    core_config.watchdog = options_.watchdog;

    // Pixel p runs on device thread p mod T (T threads in all), in round p / T; one
    // work item is one chunk of one round.
    const std::uint64_t pixels = std::uint64_t(launch_.width) * std::uint64_t(launch_.height);
    const auto threads = static_cast<std::uint64_t>(config_.shader_cores) * config_.threads_per_core;
    const auto chunk = static_cast<std::uint64_t>(config_.chunk_size);
    const std::uint64_t chunks_per_round = threads / chunk;
    const std::uint64_t items = (pixels + chunk - 1) / chunk;

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
        const std::uint64_t round = item / chunks_per_round, c = item % chunks_per_round;
        lanes.clear();
        for (std::uint64_t l = 0; l < chunk; ++l) {
          const std::uint64_t g = c * chunk + l;  // device thread
          const std::uint64_t p = round * threads + g;
          if (p >= pixels) break;
          lanes.push_back({static_cast<std::uint32_t>(g), static_cast<std::uint32_t>(g / config_.threads_per_core),
                           static_cast<std::uint32_t>((g % config_.threads_per_core) / chunk),
                           static_cast<std::uint32_t>(l), static_cast<std::uint32_t>(p)});
        }
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

  spec::HardwareConfig config_;
  fp::Format format_;
  FunctionalOptions options_;
  std::vector<std::uint8_t> image_;
  ImageLayout layout_;
  isa::Firmware firmware_;
  std::vector<std::uint32_t> shader_table_;
  bool has_firmware_ = false;
  Launch launch_;
  std::optional<functional::DeviceMemory> memory_;
  std::future<void> frame_;
  DeviceStats stats_;
};

}  // namespace

std::unique_ptr<Device> make_functional_device(const spec::HardwareConfig& config, fp::Format format,
                                               const FunctionalOptions& options) {
  return std::make_unique<FunctionalDevice>(config, format, options);
}

}  // namespace rpu::device
