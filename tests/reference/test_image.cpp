// PNG holds 8-bit sRGB, EXR linear float; both read back as written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

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

// A lit 6x5 image and the same with some pixels dark: a lone dark pixel is a dot, a pixel
// just above the ratio is not dark, a corner counts its three neighbours, and a dark band
// (a shadow, or a surface the reference lacks) has no dots.
TEST(Image, DarkDotsAreIsolatedPixelsUnderTheRatio) {
  Image reference(6, 5);
  for (glm::vec3& p : reference.pixels) p = glm::vec3(0.5f);
  Image test = reference;
  EXPECT_EQ(dark_dots(reference, test), 0u);
  test.at(1, 1) = glm::vec3(0.0f);
  test.at(4, 1) = glm::vec3(static_cast<float>(0.5 * kDarkDotRatio) + 0.01f);
  EXPECT_EQ(dark_dots(reference, test), 1u);
  test.at(5, 0) = glm::vec3(0.1f);  // none of its 3 neighbours dark
  EXPECT_EQ(dark_dots(reference, test), 2u);
  for (int x = 0; x < 6; ++x) {  // rows 3 and 4: each pixel has 3 of 5 or 5 of 8 dark
    test.at(x, 3) = glm::vec3(0.0f);
    test.at(x, 4) = glm::vec3(0.0f);
  }
  EXPECT_EQ(dark_dots(reference, test), 2u);
  reference.at(1, 1) = glm::vec3(0.0f);  // nothing is under 0.6 of black
  EXPECT_EQ(dark_dots(reference, test), 1u);
  EXPECT_THROW(dark_dots(reference, Image(5, 5)), Error);

  // A dark plus in a 3x3 image: its centre has 4 of 8 neighbours dark, which is not
  // fewer than half, its arms 3 of 5: no dots.
  Image lit(3, 3);
  for (glm::vec3& p : lit.pixels) p = glm::vec3(0.5f);
  Image plus = lit;
  for (const auto& [x, y] : {std::pair{1, 1}, {0, 1}, {2, 1}, {1, 0}, {1, 2}}) plus.at(x, y) = glm::vec3(0.0f);
  EXPECT_EQ(dark_dots(lit, plus), 0u);
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
