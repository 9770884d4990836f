#include "device/render_frame.hpp"

namespace rpu::device {

Image render_frame(Device& device, const Scene& scene, const MemoryImage& image, const isa::Firmware& firmware,
                   const RenderSettings& settings, const ProgressCallback& progress) {
  device.load_image(image.bytes, scene.source);
  device.load_firmware(firmware, shader_names(scene));
  device.launch({settings.width, settings.height, settings.spp, settings.max_depth, settings.seed}, progress);
  device.wait();
  const std::vector<glm::vec4> fb = device.read_framebuffer();
  Image out(settings.width, settings.height);
  for (std::size_t i = 0; i < fb.size(); ++i) out.pixels[i] = glm::vec3(fb[i]);
  return out;
}

}  // namespace rpu::device
