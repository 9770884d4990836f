// PNG holds 8-bit sRGB, EXR linear float; both read back as written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

#include "common/error.hpp"
#include "image/image.hpp"

namespace rpu {
namespace {

TEST(Image, SrgbEncodingMatchesIec61966) {
  EXPECT_EQ(srgb_encode_8bit(0.0), 0);
  EXPECT_EQ(srgb_encode_8bit(1.0), 255);
  EXPECT_EQ(srgb_encode_8bit(2.0), 255);   // clamped
  EXPECT_EQ(srgb_encode_8bit(-1.0), 0);    // clamped
  EXPECT_EQ(srgb_encode_8bit(0.5), 188);   // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_EQ(srgb_encode_8bit(0.18), 118);  // middle grey: 0.4614
  EXPECT_NEAR(srgb_encode(0.0031308), 12.92 * 0.0031308, 1e-12);  // the linear segment
}

class ImageFiles : public ::testing::Test {
 protected:
  // One directory per test and process: ctest runs these tests in parallel.
  std::filesystem::path dir_ = std::filesystem::temp_directory_path() /
                               (std::string("rpu_test_image_") +
                                ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                                std::to_string(getpid()));
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  static Image ramp() {
    Image image(4, 2);
    for (int x = 0; x < 4; ++x) {
      image.at(x, 0) = glm::vec3(x / 3.0f, 0.5f, 1.5f);
      image.at(x, 1) = glm::vec3(0.18f, 0.0f, 0.25f * x);
    }
    return image;
  }
};

TEST_F(ImageFiles, ExrRoundTripsLinearValuesExactly) {
  const Image image = ramp();
  write_image(image, dir_ / "ramp.exr");
  const Image back = read_image(dir_ / "ramp.exr");
  ASSERT_EQ(back.width, 4);
  ASSERT_EQ(back.height, 2);
  EXPECT_EQ(back.pixels, image.pixels);
}

TEST_F(ImageFiles, PngHoldsSrgbCodes) {
  const Image image = ramp();
  write_image(image, dir_ / "ramp.png");
  const Image back = read_image(dir_ / "ramp.png");
  ASSERT_EQ(back.width, 4);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_FLOAT_EQ(back.pixels[i][c] * 255.0f, srgb_encode_8bit(image.pixels[i][c])) << i << "," << c;
    }
  }
}

TEST_F(ImageFiles, UnknownExtensionIsAnErrorNamingTheFile) {
  try {
    write_image(ramp(), dir_ / "out.bmp");
    FAIL() << "expected rpu::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out.bmp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(".png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rpu
