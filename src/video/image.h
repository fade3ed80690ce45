// An 8-bit RGB picture and the comparisons used by visual regression tests.
#pragma once

#include <cstdint>
#include <vector>

namespace tissu {

// Pixels are stored row by row, top row first, 3 bytes (R, G, B) per pixel, no row padding.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3 bytes

  Image() = default;
  Image(int width, int height);  // all black
  std::size_t byte_size() const { return std::size_t(width) * std::size_t(height) * 3; }
  std::uint8_t* pixel(int x, int y) { return rgb.data() + (std::size_t(y) * width + x) * 3; }
  const std::uint8_t* pixel(int x, int y) const { return rgb.data() + (std::size_t(y) * width + x) * 3; }
};

struct ImageDiff {
  double fraction_over_threshold = 0;  // pixels whose largest channel difference is > threshold, 0..1
  double mean_abs_diff = 0;            // mean |a - b| over all channels, 0..255
  int max_diff = 0;                    // largest channel difference, 0..255
  // Peak signal-to-noise ratio in dB, 10 log10(255^2 / mean squared channel difference);
  // infinity for identical images.
  double psnr_db = 0;
};

// The tolerance of visual regression, shared by the golden-frame tests and `tissu compare`:
// two frames match when at most max_fraction_over of their pixels differ by more than
// threshold (out of 255) in some channel, and their mean channel difference is under
// max_mean_difference.
struct FrameTolerance {
  int threshold = 8;
  double max_fraction_over = 0.005;
  double max_mean_difference = 1.0;

  // `diff` must come from compare_images(a, b, threshold).
  bool accepts(const ImageDiff& diff) const;
};

// Throws std::invalid_argument when the sizes differ.
ImageDiff compare_images(const Image& a, const Image& b, int threshold = FrameTolerance{}.threshold);

// |a - b| per channel multiplied by `gain` and clamped, so small differences become visible.
Image difference_image(const Image& a, const Image& b, int gain = 8);

// Swaps rows top to bottom, e.g. for a bottom-up OpenGL read-back.
void flip_vertically(Image& image);

}  // namespace tissu
