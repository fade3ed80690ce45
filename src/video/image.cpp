#include "video/image.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace tissu {

static std::size_t checked_byte_size(int width, int height) {
  if (width < 0 || height < 0) {
    throw std::invalid_argument("image size must not be negative, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  }
  return std::size_t(width) * std::size_t(height) * 3;
}

Image::Image(int w, int h) : width(w), height(h), rgb(checked_byte_size(w, h), 0) {}

static void require_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height));
  }
  if (a.rgb.size() != a.byte_size() || b.rgb.size() != b.byte_size()) {
    throw std::invalid_argument("image pixel buffer does not match its width and height");
  }
}

ImageDiff compare_images(const Image& a, const Image& b, int threshold) {
  require_same_size(a, b);
  const std::size_t pixels = std::size_t(a.width) * a.height;
  ImageDiff diff;
  diff.psnr_db = std::numeric_limits<double>::infinity();
  if (pixels == 0) return diff;
  std::size_t over = 0;
  std::uint64_t sum = 0;
  std::uint64_t sum_of_squares = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    int pixel_max = 0;
    for (int c = 0; c < 3; ++c) {
      const int d = std::abs(int(a.rgb[p * 3 + c]) - int(b.rgb[p * 3 + c]));
      sum += d;
      sum_of_squares += std::uint64_t(d * d);
      pixel_max = std::max(pixel_max, d);
    }
    if (pixel_max > threshold) ++over;
    diff.max_diff = std::max(diff.max_diff, pixel_max);
  }
  diff.fraction_over_threshold = double(over) / double(pixels);
  diff.mean_abs_diff = double(sum) / double(pixels * 3);
  if (sum_of_squares > 0) {
    const double mean_square = double(sum_of_squares) / double(pixels * 3);
    diff.psnr_db = 10.0 * std::log10(255.0 * 255.0 / mean_square);
  }
  return diff;
}

bool FrameTolerance::accepts(const ImageDiff& diff) const {
  return diff.fraction_over_threshold <= max_fraction_over && diff.mean_abs_diff < max_mean_difference;
}

Image difference_image(const Image& a, const Image& b, int gain) {
  require_same_size(a, b);
  Image out(a.width, a.height);
  for (std::size_t i = 0; i < out.rgb.size(); ++i) {
    const int d = std::abs(int(a.rgb[i]) - int(b.rgb[i])) * gain;
    out.rgb[i] = std::uint8_t(std::min(d, 255));
  }
  return out;
}

void flip_vertically(Image& image) {
  const std::size_t row = std::size_t(image.width) * 3;
  for (int top = 0, bottom = image.height - 1; top < bottom; ++top, --bottom) {
    std::swap_ranges(image.rgb.begin() + top * row, image.rgb.begin() + (top + 1) * row,
                     image.rgb.begin() + bottom * row);
  }
}

}  // namespace tissu
