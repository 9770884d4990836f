#pragma once

#include <string>
#include <vector>

#include "device/device.hpp"
#include "image/image.hpp"
#include "isa/firmware.hpp"
#include "memory/memory_image.hpp"
#include "render/render.hpp"
#include "scene/scene.hpp"

namespace rpu::device {

// One frame of a scene on a device, the way every host program does it: load the
// image and the firmware (with the scene's shader table), launch, wait, read back. A
// selected frame (settings.select) is two launches, the second reading the first's
// framebuffer; the device's stats() are the frame's.
Image render_frame(Device& device, const Scene& scene, const MemoryImage& image, const isa::Firmware& firmware,
                   const RenderSettings& settings, const ProgressCallback& progress = {});

}  // namespace rpu::device
