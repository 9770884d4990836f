#pragma once

#include <future>
#include <optional>
#include <vector>

#include "device/device.hpp"
#include "functional/device_memory.hpp"
#include "functional/pixel_map.hpp"
#include "functional/shader_core.hpp"
#include "memory/memory_image.hpp"

namespace rpu::device {

// What every backend does the same way: image and firmware loading, launch checks,
// the device memory of a frame, the frame on its own host thread, read-back. A
// backend implements run().
class DeviceBase : public Device {
 public:
  DeviceBase(const spec::HardwareConfig& config, fp::Format format) : config_(config), format_(format) {}
  ~DeviceBase() override;

  void load_image(std::vector<std::uint8_t> image, const std::string& source) override;
  void load_firmware(isa::Firmware firmware, std::vector<std::string> shader_names) override;
  void launch(const Launch& launch, ProgressCallback progress) override;
  void wait() override;
  std::vector<glm::vec4> read_framebuffer() const override;
  DeviceStats stats() const override { return stats_; }

 protected:
  // Runs the launched frame (on the frame's host thread); throws rpu::Error on a fault.
  virtual void run(const ProgressCallback& progress) = 0;
  // Waits for a running frame, dropping its error. A backend's destructor calls it: the
  // frame runs the backend's run(), so it must end before the backend does.
  void end_frame() noexcept;

  std::uint64_t pixels() const { return std::uint64_t(launch_.width) * std::uint64_t(launch_.height); }
  std::uint64_t device_threads() const {
    return static_cast<std::uint64_t>(config_.shader_cores) * static_cast<std::uint64_t>(config_.threads_per_core);
  }
  // Which thread runs which pixel (functional::PixelMap, as the RTL assigns them).
  functional::PixelMap pixel_map() const { return functional::PixelMap::of(config_, pixels()); }
  // The lanes of chunk `chunk` (counted over the chip, core by core) in round `round`;
  // empty past the last pixel.
  void lanes_of(std::uint64_t round, std::uint64_t chunk, std::vector<functional::ShaderCore::Lane>& lanes) const;
  functional::ShaderCoreConfig core_config(std::uint64_t watchdog) const;
  // Pass 1 of a selected frame: run() adds its statistics to the frame's (stats_).
  bool continues_frame() const { return launch_.pass > 0; }

  spec::HardwareConfig config_;
  fp::Format format_;
  std::vector<std::uint8_t> image_;
  ImageLayout layout_;
  isa::Firmware firmware_;
  Launch launch_;
  std::optional<functional::DeviceMemory> memory_;
  DeviceStats stats_;

 private:
  void idle();
  void check_selection(const Launch& launch) const;
  void check_firmware_needs(const Launch& launch) const;

  std::vector<std::uint32_t> shader_table_;
  bool has_firmware_ = false;
  std::future<void> frame_;
};

}  // namespace rpu::device
