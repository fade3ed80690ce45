// RGB to YUV 4:2:0 (BT.709, limited range), as the H.264 writer stores frames.
#pragma once

#include <cstdint>

namespace tissu {

// Converts `width` x `height` RGB8 pixels (rows of `rgb_stride` bytes, top to bottom) into
// the planes `y` (width x height) and `u`, `v` (width/2 x height/2). Both sizes must be
// even. Luma is per pixel; each chroma sample is that of the mean of its 2x2 block
// (centred between the four pixels). Integer arithmetic with 16-bit coefficients, the same
// bytes on every processor (SIMD through Highway, chosen at run time).
void rgb_to_yuv420(const std::uint8_t* rgb, int rgb_stride, int width, int height, std::uint8_t* y,
                   int y_stride, std::uint8_t* u, int u_stride, std::uint8_t* v, int v_stride);

// The same, one pixel at a time (the reference that tests compare against).
void rgb_to_yuv420_scalar(const std::uint8_t* rgb, int rgb_stride, int width, int height, std::uint8_t* y,
                          int y_stride, std::uint8_t* u, int u_stride, std::uint8_t* v, int v_stride);

}  // namespace tissu
