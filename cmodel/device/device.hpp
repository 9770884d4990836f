#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "common/stats_tree.hpp"
#include "fp/format.hpp"
#include "functional/shader_core.hpp"
#include "isa/firmware.hpp"
#include "render/render.hpp"
#include "rpu/spec.hpp"

// The host's one interface to every view of the chip (docs/architecture.md "Four
// views"): load a memory image and firmware, launch a frame, wait, read the
// framebuffer and the statistics. The functional backend is the golden model; the
// cycle and RTL backends sit behind the same interface.
namespace rpu::device {

struct Launch {
  int width = 0, height = 0;
  int spp = 1;
  int max_depth = 5;
  std::uint32_t seed = 1;
  // Selected ray tracing (docs/selection.md) takes two launches, pass 0 and pass 1; pass
  // 1 continues the frame (its statistics add to pass 0's) and reads `corners`, pass
  // 0's framebuffer, which the launch block carries.
  Selection select = {};
  int pass = 0;
  std::vector<glm::vec4> corners = {};
};

struct DeviceStats {
  functional::ShaderStats shader;
  double host_seconds = 0.0;  // wall time of the frame (both launches of a selected one)
  int host_threads = 1;
  // Everything the backend counted, for the writers (common/stats_tree.hpp): the
  // functional backend's shader work; the cycle backend's also its timing
  // (cycle::report).
  StatsTree report;
};

class Device {
 public:
  virtual ~Device() = default;
  virtual std::string_view backend() const = 0;

  // Validates the image (rpu::Error naming `source`, the section and the offset).
  virtual void load_image(std::vector<std::uint8_t> image, const std::string& source) = 0;
  // `shader_names[id]` is the scene's shader with that id (rpu::shader_names); the
  // firmware must have the code label "hit_<name>" for each, and "raygen".
  virtual void load_firmware(isa::Firmware firmware, std::vector<std::string> shader_names) = 0;
  // Starts a frame; `progress` (optional) is called from worker threads.
  virtual void launch(const Launch& launch, ProgressCallback progress = {}) = 0;
  // Waits for the frame; rethrows its fault (rpu::Error) if a shader faulted.
  virtual void wait() = 0;
  // Linear RGBA per pixel, row 0 first.
  virtual std::vector<glm::vec4> read_framebuffer() const = 0;
  // The frame's: a launch of pass 1 adds its counts to pass 0's.
  virtual DeviceStats stats() const = 0;
};

struct FunctionalOptions {
  int host_threads = 0;       // 0: all cores. The image never depends on it.
  bool fast_path = true;      // fp32 on host float (identical bits)
  std::uint64_t watchdog = 50'000'000;  // instructions per thread and pixel
  // rpu render --pixel: the pixel (y * width + x) whose every instruction goes to
  // `trace`, one ShaderCore::trace_line each.
  std::optional<std::uint32_t> trace_pixel;
  std::function<void(const std::string&)> trace;
};

std::unique_ptr<Device> make_functional_device(const spec::HardwareConfig& config, fp::Format format,
                                               const FunctionalOptions& options = {});

// The shader table of a scene: entry i is the code address of the firmware's label
// "hit_<shader_names[i]>"; rpu::Error naming a missing label.
std::vector<std::uint32_t> shader_table(const isa::Firmware& firmware, std::span<const std::string> shader_names);

// The launch block, the shader table and (pass 1 of a selected frame) the corners'
// framebuffer, which the firmware reads at spec::memory::kDeviceLaunchBase
// (spec/memory_map.toml [launch]). Exposed for the tests that check it field by field.
std::vector<std::uint8_t> make_launch_block(std::span<const std::uint8_t> image, const ImageLayout& layout,
                                            const Launch& launch, std::span<const std::uint32_t> shader_table);

}  // namespace rpu::device
