// libFuzzer target: validate_memory_image on arbitrary bytes. It may reject an image
// only with rpu::Error; any other exception, crash, leak or UB is a finding. An image
// it accepts is read through once more by re-validating its layout's sections, which
// must all lie inside the input.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "common/error.hpp"
#include "memory/memory_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  try {
    const rpu::ImageLayout layout = rpu::validate_memory_image(bytes, "fuzz.rpu");
    for (const rpu::ImageSection* s : {&layout.scene, &layout.kd_nodes, &layout.prim_refs, &layout.isect_records,
                                       &layout.vertex_normals, &layout.vertex_uvs, &layout.triangles,
                                       &layout.materials, &layout.lights, &layout.camera}) {
      if (std::uint64_t{s->offset} + s->bytes > size) std::abort();
    }
  } catch (const rpu::Error&) {
    // The one way to reject an image.
  }
  return 0;
}
