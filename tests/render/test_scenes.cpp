#include "test_scenes.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace tissu::test {

FrameContent flat_cloth(int n, double size, double height) {
  FrameContent frame;
  const double step = size / n;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -0.5 * size + i * step, y = -0.5 * size + j * step;
      frame.positions.emplace_back(x, y, height);
      frame.rest_uv.emplace_back(x + 0.5 * size, y + 0.5 * size);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      frame.triangles.emplace_back(a, b, d);
      frame.triangles.emplace_back(a, d, c);
    }
  }
  return frame;
}

FrameContent draped_cloth(int n, double size, double radius) {
  FrameContent frame = flat_cloth(n, size, radius);
  for (Vec3& p : frame.positions) {
    const double r = std::hypot(p.x(), p.y());
    if (r < radius * std::sin(1.2)) {  // on the sphere cap
      p.z() = std::sqrt(radius * radius - r * r);
    } else {  // hanging down from the rim, with some folds
      const double rim = radius * std::sin(1.2);
      const double hang = r - rim;
      const double angle = std::atan2(p.y(), p.x());
      const double fold = 0.04 * radius * std::sin(8 * angle) * std::min(1.0, hang / radius);
      const double out = rim + 0.25 * hang + fold;
      p = Vec3(out * std::cos(angle), out * std::sin(angle), radius * std::cos(1.2) - 0.95 * hang);
    }
  }
  return frame;
}

ObstacleShape sphere(const Vec3& center, double radius) {
  ObstacleShape s;
  s.kind = ObstacleShape::Kind::Sphere;
  s.center = center;
  s.radius = radius;
  return s;
}

RenderSettings plain_settings(int width, int height) {
  RenderSettings s;
  s.width = width;
  s.height = height;
  s.msaa = 1;
  s.background.top = s.background.bottom = Vec3::Zero();
  s.lights = {Light{Vec3(0, 0, -1), Vec3::Ones(), 1.0}};
  s.cloth.pattern = ClothPattern::None;
  return s;
}

Rgb pixel(const std::vector<uint8_t>& image, int width, int x, int y) {
  const size_t i = (static_cast<size_t>(y) * width + x) * 3;
  return {image.at(i), image.at(i + 1), image.at(i + 2)};
}

uint64_t image_hash(const std::vector<uint8_t>& image) {
  uint64_t h = 1469598103934665603ull;
  for (uint8_t byte : image) {
    h ^= byte;
    h *= 1099511628211ull;
  }
  return h;
}

void write_ppm(const std::string& path, const std::vector<uint8_t>& rgb, int width, int height) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << width << " " << height << "\n255\n";
  out.write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size()));
  if (!out) throw std::runtime_error(path + ": cannot write image");
}

}  // namespace tissu::test

// Mesa keeps a few hundred bytes per OSMesa context until exit (its buffer list);
// with TISSU_SANITIZE=ON LeakSanitizer would fail every GL test on them.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }
