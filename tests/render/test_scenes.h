// Frames used by the render tests and the timing program.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/frame_content.h"
#include "render/render_settings.h"

namespace tissu::test {

// An n x n grid of squares (2 n^2 triangles) of side `size` centred at the origin
// in the plane z = height, counter-clockwise seen from +z; rest uv = x, y + size/2.
FrameContent flat_cloth(int n, double size, double height = 0.0);

// The flat grid bent over a sphere of radius `radius` at the origin, as if draped:
// points within the sphere's footprint lie on it, the rest hangs down.
FrameContent draped_cloth(int n, double size, double radius);

ObstacleShape sphere(const Vec3& center, double radius);

// Small settings for fast tests: plain black background, one light along -z, MSAA off.
RenderSettings plain_settings(int width, int height);

// Pixel (x, y) of an RGB image, y from the top.
struct Rgb {
  int r, g, b;
};
Rgb pixel(const std::vector<uint8_t>& image, int width, int x, int y);

// FNV-1a hash of an image, printed by the timing program to compare runs.
uint64_t image_hash(const std::vector<uint8_t>& image);

// Writes a binary PPM (for looking at a frame).
void write_ppm(const std::string& path, const std::vector<uint8_t>& rgb, int width, int height);

}  // namespace tissu::test
