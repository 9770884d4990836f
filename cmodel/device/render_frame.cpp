#include "device/render_frame.hpp"

namespace rpu::device {

Image render_frame(Device& device, const Scene& scene, const MemoryImage& image, const isa::Firmware& firmware,
                   const RenderSettings& settings, const ProgressCallback& progress) {
  device.load_image(image.bytes, scene.source);
  device.load_firmware(firmware, shader_names(scene));
  Launch launch{settings.width, settings.height, settings.spp, settings.max_depth, settings.seed};
  launch.select = settings.select;
  device.launch(launch, progress);
  device.wait();
  if (launch.select.enabled()) {
    // Pass 1 reads pass 0's corners (docs/selection.md).
    launch.pass = 1;
    launch.corners = device.read_framebuffer();
    device.launch(launch, progress);
    device.wait();
  }
  const std::vector<glm::vec4> fb = device.read_framebuffer();
  Image out(settings.width, settings.height);
  for (std::size_t i = 0; i < fb.size(); ++i) out.pixels[i] = glm::vec3(fb[i]);
  return out;
}

}  // namespace rpu::device
