// The committed fuzz seeds are exactly what the writer produces today.
#include <gtest/gtest.h>

#include <filesystem>

#include "seed_images.hpp"

namespace rpu {
namespace {

TEST(FuzzSeeds, CommittedSeedImagesMatchTheWriter) {
  const std::filesystem::path dir = std::filesystem::path(RPU_SOURCE_DIR) / "tests/fuzz/corpus/memory_image";
  for (const auto& [name, image] : test::seed_images()) {
    EXPECT_EQ(load_memory_image(dir / name).bytes, image.bytes)
        << name << " is stale: run build/<preset>/tests/memory/write_seed_images " << dir.string();
  }
}

}  // namespace
}  // namespace rpu
