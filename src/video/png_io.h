// PNG files of RGB images, for frame dumps and golden-frame comparisons.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "video/image.h"

namespace tissu {

// `rgb` (width * height * 3 bytes, rows top to bottom) as the bytes of an 8-bit RGB PNG:
// the "up" row filter, deflated by ISA-L's igzip at level 1 (fast; files about the size of
// zlib's level 1).
std::vector<std::uint8_t> encode_png(const std::uint8_t* rgb, int width, int height);

// Writes encode_png's bytes to `path`. The file appears complete or not at all (written
// under a temporary name, then renamed). Throws OutputError naming `path` on failure.
void write_png(const std::string& path, const std::uint8_t* rgb, int width, int height);
void write_png(const std::string& path, const Image& image);

// Reads any 8- or 16-bit PNG (gray, palette, RGB, with or without alpha) as 8-bit RGB;
// alpha is dropped. Throws InputError naming `path` when the file is missing or invalid.
Image read_png(const std::string& path);

}  // namespace tissu
