#include <cmath>
#include <cstring>
#include <numbers>

#include <fmt/format.h>

#include "common/error.hpp"
#include "device/device.hpp"
#include "memory/little_endian.hpp"
#include "render/sampling.hpp"

namespace rpu::device {

namespace mm = spec::memory;

std::vector<std::uint8_t> make_launch_block(std::span<const std::uint8_t> image, const ImageLayout& layout,
                                            const Launch& launch, std::span<const std::uint32_t> shader_table) {
  // The camera frame of docs/shading.md §2, the reference's, computed in double from
  // the image's fp32 camera record and rounded once: the firmware then needs no tangent.
  const std::size_t cam = layout.camera.offset;
  Camera camera;
  camera.position = glm::dvec3(load_float4(image, cam + mm::kCameraPositionAt));
  camera.look_at = glm::dvec3(load_float4(image, cam + mm::kCameraLookAtAt));
  camera.up = glm::dvec3(load_float4(image, cam + mm::kCameraUpAt));
  camera.vfov_degrees = load_f32(image, cam + mm::kCameraVfovAt);
  // Cameras the reference renders in double but the chip cannot: refused, not rendered
  // in one colour.
  if (camera.look_at == camera.position) {
    throw Error("the camera's look_at equals its position in fp32, as the memory image holds them: the chip has no "
                "view direction; move them further apart (the reference, in double, may still tell them apart)");
  }
  const CameraModel frame(camera, launch.width, launch.height);
  // The image plane's half extent at distance 1 below fp32's precision at 1: every
  // pixel's ray is forward once rounded.
  if (std::max(frame.half_width(), frame.half_height()) < std::ldexp(1.0, -23)) {
    const double least_degrees = 2 * std::atan(std::ldexp(1.0, -23)) * 180 / std::numbers::pi;
    throw Error(fmt::format("the camera's vfov {:.3g} degrees: the image plane is {:.3g} across at distance 1, below "
                            "fp32's precision (2^-23), so every pixel's ray would be the same on the chip; give at "
                            "least {:.3g} degrees",
                            camera.vfov_degrees, 2 * frame.half_width(), least_degrees));
  }

  // The shader table follows the block; pass 1's corners follow it on a 16-byte boundary.
  const std::size_t table_end = mm::kLaunchBytes + 4 * shader_table.size();
  const std::size_t corners_at = (table_end + 15) / 16 * 16;
  const std::size_t bytes =
      launch.corners.empty() ? table_end : corners_at + launch.corners.size() * sizeof(glm::vec4);
  std::vector<std::uint8_t> block(bytes, 0);
  const auto u32 = [&](std::uint32_t at, std::uint32_t v) { store_u32(block, at, v); };
  const auto vec = [&](std::uint32_t at, const glm::dvec3& v) { store_float4(block, at, glm::vec4(glm::vec3(v), 0.0f)); };
  const auto section = [](const ImageSection& s) { return s.count ? mm::kDeviceImageBase + s.offset : 0u; };
  u32(mm::kLaunchWidthAt, static_cast<std::uint32_t>(launch.width));
  u32(mm::kLaunchHeightAt, static_cast<std::uint32_t>(launch.height));
  u32(mm::kLaunchSppAt, static_cast<std::uint32_t>(launch.spp));
  u32(mm::kLaunchMaxDepthAt, static_cast<std::uint32_t>(launch.max_depth));
  u32(mm::kLaunchSeedAt, launch.seed);
  u32(mm::kLaunchFramebufferAt, mm::kDeviceFramebufferBase);
  u32(mm::kLaunchShaderCountAt, static_cast<std::uint32_t>(shader_table.size()));
  u32(mm::kLaunchShaderTableAt, mm::kDeviceLaunchBase + mm::kLaunchBytes);
  vec(mm::kLaunchOriginAt, frame.origin());
  vec(mm::kLaunchForwardAt, frame.forward());
  vec(mm::kLaunchRightAt, frame.right() * frame.half_width());
  vec(mm::kLaunchUpAt, frame.up() * frame.half_height());
  u32(mm::kLaunchSceneAt, section(layout.scene));
  u32(mm::kLaunchLightsAt, section(layout.lights));
  u32(mm::kLaunchMaterialsAt, section(layout.materials));
  u32(mm::kLaunchTrianglesAt, section(layout.triangles));
  u32(mm::kLaunchPositionsAt, section(layout.vertex_positions));
  u32(mm::kLaunchNormalsAt, section(layout.vertex_normals));
  u32(mm::kLaunchUvsAt, section(layout.vertex_uvs));
  u32(mm::kLaunchCameraAt, section(layout.camera));
  if (launch.select.enabled()) {
    const auto b = static_cast<std::uint32_t>(launch.select.block);
    u32(mm::kLaunchSelectBlockAt, b);
    u32(mm::kLaunchSelectReciprocalAt, static_cast<std::uint32_t>(((std::uint64_t{1} << 32) + b - 1) / b));
    store_f32(block, mm::kLaunchSelectThresholdAt, launch.select.threshold);
    u32(mm::kLaunchSelectKeyAt, launch.select.key);
    u32(mm::kLaunchSelectPassAt, static_cast<std::uint32_t>(launch.pass));
    if (!launch.corners.empty()) {
      u32(mm::kLaunchSelectCornersAt, mm::kDeviceLaunchBase + static_cast<std::uint32_t>(corners_at));
      std::memcpy(block.data() + corners_at, launch.corners.data(), launch.corners.size() * sizeof(glm::vec4));
    }
  }
  for (std::size_t i = 0; i < shader_table.size(); ++i) u32(static_cast<std::uint32_t>(mm::kLaunchBytes + 4 * i), shader_table[i]);
  return block;
}

}  // namespace rpu::device
