#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "video/image.h"

namespace tissu {
namespace {

Image filled(int width, int height, std::uint8_t value) {
  Image image(width, height);
  std::fill(image.rgb.begin(), image.rgb.end(), value);
  return image;
}

TEST(CompareImages, IdenticalImagesDoNotDiffer) {
  const Image a = filled(10, 10, 77);
  const ImageDiff diff = compare_images(a, a, 0);
  EXPECT_EQ(diff.fraction_over_threshold, 0.0);
  EXPECT_EQ(diff.mean_abs_diff, 0.0);
  EXPECT_EQ(diff.max_diff, 0);
}

TEST(CompareImages, CountsPixelsOverTheThresholdByTheirLargestChannel) {
  const Image a = filled(10, 10, 100);  // 100 pixels
  Image b = a;
  b.pixel(0, 0)[0] = 120;                                                  // +20 in red: over 8
  b.pixel(1, 0)[2] = 80;                                                   // -20 in blue: over 8
  b.pixel(2, 0)[1] = 108;                                                  // +8: not over 8
  b.pixel(3, 0)[0] = 109, b.pixel(3, 0)[1] = 109, b.pixel(3, 0)[2] = 109;  // +9 in all: over
  const ImageDiff diff = compare_images(a, b, 8);
  EXPECT_DOUBLE_EQ(diff.fraction_over_threshold, 3.0 / 100.0);
  EXPECT_DOUBLE_EQ(diff.mean_abs_diff, (20.0 + 20.0 + 8.0 + 27.0) / 300.0);
  EXPECT_EQ(diff.max_diff, 20);
  EXPECT_DOUBLE_EQ(compare_images(a, b, 7).fraction_over_threshold, 4.0 / 100.0);
  EXPECT_DOUBLE_EQ(compare_images(a, b, 20).fraction_over_threshold, 0.0);
}

TEST(CompareImages, HalfChangedImage) {
  const Image a = filled(4, 2, 0);
  Image b = a;
  for (int x = 0; x < 4; ++x) b.pixel(x, 1)[1] = 255;  // bottom row green
  const ImageDiff diff = compare_images(a, b, 8);
  EXPECT_DOUBLE_EQ(diff.fraction_over_threshold, 0.5);
  EXPECT_DOUBLE_EQ(diff.mean_abs_diff, 255.0 / 6.0);
  EXPECT_EQ(diff.max_diff, 255);
}

TEST(CompareImages, PsnrOfOneChangedChannel) {
  const Image a = filled(2, 1, 100);  // 6 channel values
  Image b = a;
  b.pixel(0, 0)[0] = 110;
  // Mean squared difference 10^2 / 6; PSNR = 10 log10(255^2 * 6 / 100) = 10 log10(3901.5).
  EXPECT_NEAR(compare_images(a, b).psnr_db, 35.912316, 1e-6);
}

TEST(CompareImages, PsnrOfIdenticalImagesIsInfinite) {
  const Image a = filled(3, 3, 9);
  EXPECT_TRUE(std::isinf(compare_images(a, a).psnr_db));
  EXPECT_GT(compare_images(a, a).psnr_db, 0.0);
}

TEST(CompareImages, PsnrOfBlackAgainstWhiteIsZero) {
  EXPECT_NEAR(compare_images(filled(2, 2, 0), filled(2, 2, 255)).psnr_db, 0.0, 1e-12);
}

TEST(FrameTolerance, DefaultsAreTheGoldenFrameRule) {
  const FrameTolerance tolerance;
  EXPECT_EQ(tolerance.threshold, 8);
  EXPECT_EQ(tolerance.max_fraction_over, 0.005);
  EXPECT_EQ(tolerance.max_mean_difference, 1.0);
}

TEST(FrameTolerance, LimitsTheFractionOverAndTheMean) {
  const FrameTolerance tolerance;
  ImageDiff diff;
  diff.fraction_over_threshold = 0.005;  // at most: accepted
  diff.mean_abs_diff = 0.99;
  EXPECT_TRUE(tolerance.accepts(diff));
  diff.fraction_over_threshold = 0.0051;
  EXPECT_FALSE(tolerance.accepts(diff));
  diff.fraction_over_threshold = 0;
  diff.mean_abs_diff = 1.0;  // must be under: rejected
  EXPECT_FALSE(tolerance.accepts(diff));
}

TEST(CompareImages, DifferentSizesAreRejected) {
  EXPECT_THROW(compare_images(Image(4, 4), Image(4, 5), 8), std::invalid_argument);
}

TEST(ImageSize, NegativeSizesAreRejected) { EXPECT_THROW(Image(-1, 4), std::invalid_argument); }

TEST(DifferenceImage, AmplifiesAndClamps) {
  Image a = filled(2, 1, 100);
  Image b = a;
  b.pixel(0, 0)[0] = 103;  // 3 * 8 = 24
  b.pixel(1, 0)[2] = 0;    // 100 * 8 clamps to 255
  const Image d = difference_image(a, b, 8);
  EXPECT_EQ((std::vector<int>(d.rgb.begin(), d.rgb.end())), (std::vector<int>{24, 0, 0, 0, 0, 255}));
}

TEST(FlipVertically, SwapsRows) {
  Image image(1, 3);
  image.pixel(0, 0)[0] = 1, image.pixel(0, 1)[0] = 2, image.pixel(0, 2)[0] = 3;
  flip_vertically(image);
  EXPECT_EQ(image.pixel(0, 0)[0], 3);
  EXPECT_EQ(image.pixel(0, 1)[0], 2);
  EXPECT_EQ(image.pixel(0, 2)[0], 1);
}

}  // namespace
}  // namespace tissu
