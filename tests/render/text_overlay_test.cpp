// Text blended on the processor (render/image/text_overlay.h): where it lands, its
// colours, its drop shadow, and that it never writes outside the image.
#include "render/image/text_overlay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tissu {
namespace {

constexpr int kW = 320, kH = 240;

struct Bounds {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;  // inclusive; empty when x1 < x0
};

// The bounding box of the pixels that differ from `value`, and their extreme values.
Bounds changed(const std::vector<uint8_t>& rgb, uint8_t value, int* low, int* high,
               int width = kW, int height = kH) {
  Bounds b;
  *low = 255;
  *high = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint8_t* p = &rgb[(y * width + x) * 3];
      EXPECT_TRUE(p[0] == p[1] && p[1] == p[2]) << "text is grey, at " << x << "," << y;
      if (p[0] == value) continue;
      b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x), std::max(b.y1, y)};
      *low = std::min<int>(*low, p[0]);
      *high = std::max<int>(*high, p[0]);
    }
  }
  return b;
}

TEST(TextOverlay, NoTextLeavesTheImageAlone) {
  std::vector<uint8_t> rgb(kW * kH * 3, 90);
  TextOverlay(kW, kH).blend("", {}, rgb);
  EXPECT_EQ(std::count(rgb.begin(), rgb.end(), 90), kW * kH * 3);
}

TEST(TextOverlay, CaptionIsCentredAtTheTopInTheTextColour) {
  std::vector<uint8_t> rgb(kW * kH * 3, 0);
  TextOverlay(kW, kH).blend("Cotton on a sphere", {}, rgb);
  int low, high;
  const Bounds b = changed(rgb, 0, &low, &high);
  ASSERT_GE(b.x1, b.x0) << "no text drawn";
  EXPECT_LT(b.y1, kH / 6);                                 // in the top band
  EXPECT_NEAR(b.x0 + b.x1, kW, 4);                          // centred (shadow: 1 px right)
  EXPECT_EQ(high, 247);  // 0.97 x 255 where a glyph covers its pixel fully
}

TEST(TextOverlay, CornerLinesSitBottomLeftOverTheirShadow) {
  constexpr int w = 1280, h = 720;  // letters 25 px tall: strokes several pixels wide
  std::vector<uint8_t> rgb(w * h * 3, 255);
  TextOverlay(w, h).blend("", {"integrator: bdf2", "t = 0.500 s"}, rgb);
  int low, high;
  const Bounds b = changed(rgb, 255, &low, &high, w, h);
  ASSERT_GE(b.x1, b.x0) << "no text drawn";
  EXPECT_GT(b.y0, h / 2);
  EXPECT_LT(b.x1, w / 2);
  EXPECT_LT(b.y1, h - 10);  // one margin above the bottom edge
  // On white, only the shadow shows: 45% of white where it covers fully, and the text
  // over it brings pixels back to 0.97 x 255 at most.
  EXPECT_EQ(low, 115);
  EXPECT_LE(high, 254);
}

TEST(TextOverlay, NeverWritesOutsideATinyImage) {
  constexpr int w = 24, h = 10, guard = 4096;
  std::vector<uint8_t> rgb(w * h * 3 + guard, 200);
  TextOverlay(w, h).blend("a caption far wider than the image", {"one", "two", "three"},
                          rgb);
  EXPECT_EQ(std::count(rgb.begin() + w * h * 3, rgb.end(), 200), guard);
}

}  // namespace
}  // namespace tissu
