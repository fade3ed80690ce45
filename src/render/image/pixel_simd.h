// Pixel loops of the read-back and of FXAA in SIMD (Highway, instruction set chosen at run
// time). Integer arithmetic: the same bytes as the plain loops on every processor.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tissu {

// Drops the alpha byte of `pixels` RGBA pixels: rgb[3 i + c] = rgba[4 i + c].
void rgba_to_rgb(const std::uint8_t* rgba, std::uint8_t* rgb, std::size_t pixels);

// Rec. 601 luma in 1/256ths of `pixels` RGB pixels: (77 r + 150 g + 29 b + 128) >> 8.
void rgb_luma(const std::uint8_t* rgb, std::uint8_t* luma, std::size_t pixels);

}  // namespace tissu
