// Writes the memory-image fuzzer's seed corpus:
//   write_seed_images tests/fuzz/corpus/memory_image
#include <cstdio>
#include <filesystem>

#include "common/error.hpp"
#include "seed_images.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_seed_images DIR\n");
    return 2;
  }
  try {
    for (const auto& [name, image] : rpu::test::seed_images()) {
      rpu::save_memory_image(image, std::filesystem::path(argv[1]) / name);
    }
  } catch (const rpu::Error& e) {
    std::fprintf(stderr, "write_seed_images: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
