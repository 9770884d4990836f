#include "device/device_base.hpp"

#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "common/error.hpp"
#include "memory/little_endian.hpp"

namespace rpu::device {

namespace mm = spec::memory;

DeviceBase::~DeviceBase() { end_frame(); }

void DeviceBase::end_frame() noexcept {
  if (frame_.valid()) frame_.wait();
}

void DeviceBase::idle() {
  if (frame_.valid()) frame_.get();
}

void DeviceBase::load_image(std::vector<std::uint8_t> image, const std::string& source) {
  idle();
  layout_ = validate_memory_image(image, source);
  image_ = std::move(image);
}

std::vector<std::uint32_t> shader_table(const isa::Firmware& firmware, std::span<const std::string> shader_names) {
  std::vector<std::uint32_t> table;
  for (const std::string& name : shader_names) {
    const std::string label = "hit_" + name;
    const auto s = firmware.symbols.find(label);
    if (s == firmware.symbols.end() || s->second.kind != isa::Symbol::Kind::kCode) {
      throw Error(fmt::format("the firmware has no code label '{}' for the scene's shader '{}'", label, name));
    }
    table.push_back(s->second.value);
  }
  return table;
}

void DeviceBase::load_firmware(isa::Firmware firmware, std::vector<std::string> shader_names) {
  idle();
  // Here rather than when the frame's threads make their shader cores.
  functional::raygen_entry(firmware);
  std::vector<std::uint32_t> table = shader_table(firmware, shader_names);
  firmware_ = std::move(firmware);
  shader_table_ = std::move(table);
  has_firmware_ = true;
}

void DeviceBase::launch(const Launch& launch, ProgressCallback progress) {
  idle();
  if (image_.empty()) throw Error("launch before load_image");
  if (!has_firmware_) throw Error("launch before load_firmware");
  if (launch.width <= 0 || launch.height <= 0 || launch.spp <= 0 || launch.max_depth < 0) {
    throw Error(fmt::format("launch of {}x{} pixels, {} spp, max depth {}: sizes must be positive", launch.width,
                            launch.height, launch.spp, launch.max_depth));
  }
  const std::uint64_t n = std::uint64_t(launch.width) * std::uint64_t(launch.height);
  if (n * mm::kFramebufferBytesPerPixel > std::numeric_limits<std::uint32_t>::max() - mm::kDeviceFramebufferBase) {
    throw Error(fmt::format("a {}x{} framebuffer does not fit the device's address space", launch.width,
                            launch.height));
  }
  check_selection(launch);
  check_firmware_needs(launch);
  std::vector<std::uint8_t> block = make_launch_block(image_, layout_, launch, shader_table_);
  if (block.size() > mm::kDeviceDataBase - mm::kDeviceLaunchBase) {
    throw Error(fmt::format("the launch block of a {}x{} frame's pass 1 ({} bytes with the corners' framebuffer) "
                            "does not fit the launch segment ({} bytes at {:#010x}): render a smaller frame",
                            launch.width, launch.height, block.size(), mm::kDeviceDataBase - mm::kDeviceLaunchBase,
                            mm::kDeviceLaunchBase));
  }
  memory_.emplace(image_, std::move(block), firmware_.data, static_cast<std::uint32_t>(n));
  launch_ = launch;
  frame_ = std::async(std::launch::async, [this, progress] { run(progress); });
}

// A selected frame is pass 0 then pass 1 on the same device (device::render_frame).
void DeviceBase::check_selection(const Launch& launch) const {
  const std::uint64_t n = std::uint64_t(launch.width) * std::uint64_t(launch.height);
  if (!launch.select.enabled()) {
    if (launch.pass != 0 || !launch.corners.empty()) throw Error("a launch without selection has no pass 1 and no corners");
    return;
  }
  if (launch.select.block > static_cast<int>(mm::kSelectMaxBlock)) {
    throw Error(fmt::format("selection block {} is larger than {}", launch.select.block, mm::kSelectMaxBlock));
  }
  if (launch.pass != 0 && launch.pass != 1) throw Error(fmt::format("selection pass {} is neither 0 nor 1", launch.pass));
  if (launch.pass == 0 && !launch.corners.empty()) throw Error("pass 0 of a selected frame reads no corners");
  if (launch.pass == 1 && launch.corners.size() != n) {
    throw Error(fmt::format("pass 1 of a selected {}x{} frame needs pass 0's framebuffer of {} pixels, not {}",
                            launch.width, launch.height, n, launch.corners.size()));
  }
  if (launch.pass == 1 && (launch_.pass != 0 || !launch_.select.enabled() || launch_.width != launch.width ||
                           launch_.height != launch.height)) {
    throw Error("pass 1 of a selected frame must follow its pass 0 on the same device");
  }
}

// Firmware declares what it needs (docs/shader-core.md "The shader ABI"), so that a
// launch too deep for the configuration's stacks is refused before it runs instead of
// faulting in the middle of the frame, and a camera the firmware does not model is
// refused instead of rendered as a pinhole.
void DeviceBase::check_firmware_needs(const Launch& launch) const {
  const auto constant = [&](std::string_view name) -> std::optional<std::uint64_t> {
    const auto s = firmware_.symbols.find(name);
    if (s == firmware_.symbols.end() || s->second.kind != isa::Symbol::Kind::kConstant) return std::nullopt;
    return s->second.value;
  };
  if (const float aperture = load_f32(image_, layout_.camera.offset + mm::kCameraApertureAt);
      aperture > 0.0f && constant("FIRMWARE_THIN_LENS").value_or(0) == 0) {
    throw Error("the camera has a lens (aperture > 0) but the firmware renders a pinhole camera (it does not "
                "declare FIRMWARE_THIN_LENS): set the aperture to 0 or use firmware with a thin lens "
                "(firmware/glsl/thin_lens.rgen)");
  }
  if (launch.select.enabled() && constant("FIRMWARE_SELECTS").value_or(0) == 0) {
    throw Error(fmt::format("selection {} needs firmware with selected ray tracing (it declares FIRMWARE_SELECTS; "
                            "the built-in whitted.s does): this firmware traces every pixel",
                            to_string(launch.select)));
  }
  const int max_depth = launch.max_depth;
  const auto depth = static_cast<std::uint64_t>(max_depth);
  if (const auto entries = constant("FIRMWARE_RETURN_STACK_ENTRIES");
      entries && *entries > static_cast<std::uint64_t>(config_.call_depth)) {
    throw Error(fmt::format("the firmware needs {} return-stack entries per thread (its FIRMWARE_RETURN_STACK_ENTRIES); "
                            "config '{}' has call_depth {} (spec/configs.toml): use a configuration with more",
                            *entries, config_.name, config_.call_depth));
  }
  const std::uint64_t fixed = constant("FIRMWARE_STACK_BYTES").value_or(0);
  const std::uint64_t per_depth = constant("FIRMWARE_STACK_BYTES_PER_DEPTH").value_or(0);
  const auto have = static_cast<std::uint64_t>(config_.stack_bytes);
  if (fixed + depth * per_depth > have) {
    throw Error(fmt::format(
        "max depth {} needs {} stack bytes per thread (the firmware's FIRMWARE_STACK_BYTES {} + {} x "
        "FIRMWARE_STACK_BYTES_PER_DEPTH {}); config '{}' has stack_bytes {} (spec/configs.toml): {}",
        max_depth, fixed + depth * per_depth, fixed, max_depth, per_depth, config_.name, have,
        fixed > have ? std::string("use a configuration with more")
                     : fmt::format("use --max-depth {} or less", (have - fixed) / per_depth)));
  }
}

void DeviceBase::wait() {
  if (frame_.valid()) frame_.get();
}

std::vector<glm::vec4> DeviceBase::read_framebuffer() const {
  if (!memory_) throw Error("read_framebuffer before a launch");
  const std::span<const std::uint8_t> fb = memory_->framebuffer();
  std::vector<glm::vec4> out(fb.size() / sizeof(glm::vec4));
  std::memcpy(out.data(), fb.data(), out.size() * sizeof(glm::vec4));
  return out;
}

void DeviceBase::lanes_of(std::uint64_t round, std::uint64_t chunk,
                          std::vector<functional::ShaderCore::Lane>& lanes) const {
  const auto chunks = static_cast<std::uint64_t>(config_.threads_per_core / config_.chunk_size);
  const functional::PixelMap map = pixel_map();
  map.lanes(map.block(round, static_cast<std::uint32_t>(chunk / chunks), static_cast<std::uint32_t>(chunk % chunks)),
            lanes);
}

functional::ShaderCoreConfig DeviceBase::core_config(std::uint64_t watchdog) const {
  return functional::ShaderCoreConfig::of(config_, watchdog);
}

}  // namespace rpu::device
