// Hand-run timing (not a test): how long one 1280x720 frame takes through Mp4Writer and
// write_png on this machine. Usage: video_timing [output directory, default /tmp]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "video/mp4_writer.h"
#include "video/png_io.h"
#include "video_test_support.h"

using namespace tissu;

namespace {

// Roughly what the renderer makes: a sky gradient and a shaded, folded cloth that moves.
Image render_like(int width, int height, int index) {
  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      const bool cloth =
          x > width / 4 && x < width * 3 / 4 && y > height / 5 + (x % 97) / 8 && y < height * 4 / 5;
      if (cloth) {
        const double shade = 0.6 + 0.4 * std::sin(x * 0.05 + index * 0.1) * std::cos(y * 0.03);
        p[0] = std::uint8_t(200 * shade), p[1] = std::uint8_t(60 * shade), p[2] = std::uint8_t(50 * shade);
      } else {
        p[0] = std::uint8_t(120 + y / 12), p[1] = std::uint8_t(150 + y / 12), p[2] = std::uint8_t(200);
      }
    }
  }
  return image;
}

// Wall-clock and process CPU time (all threads); CPU time is less disturbed by other load.
struct Stopwatch {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  std::clock_t cpu = std::clock();
  double wall_ms() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count() * 1000;
  }
  double cpu_ms() const { return double(std::clock() - cpu) * 1000 / CLOCKS_PER_SEC; }
};

template <typename MakeFrame>
void time_video(const std::string& path, const char* content, int threads, MakeFrame make_frame) {
  const int frames = 120;
  std::vector<Image> input;
  for (int i = 0; i < frames; ++i) input.push_back(make_frame(i));
  Mp4Options options;
  options.encoder_threads = threads;
  const Stopwatch watch;
  Mp4Writer writer(path, 1280, 720, 30, options);
  for (const Image& frame : input) writer.write_frame(frame);
  writer.finish();
  std::printf("mp4 %-8s threads=%d: %6.1f ms wall, %6.1f ms CPU per frame (%d frames, incl. flush)\n",
              content, threads, watch.wall_ms() / frames, watch.cpu_ms() / frames, frames);
}

void time_png(const std::string& path, const char* content, const Image& image) {
  const int repeats = 20;
  const Stopwatch watch;
  for (int i = 0; i < repeats; ++i) write_png(path, image);
  std::printf("png %-8s level 1:  %6.1f ms wall, %6.1f ms CPU per frame, %zu bytes\n", content,
              watch.wall_ms() / repeats, watch.cpu_ms() / repeats, test::file_bytes(path).size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "/tmp";
  auto gradient = [](int i) { return test::moving_gradient(1280, 720, i); };
  auto rendered = [](int i) { return render_like(1280, 720, i); };
  auto noise = [](int i) { return test::noise_image(1280, 720, unsigned(i)); };
  for (int threads : {1, 2}) {
    time_video(dir + "/timing-gradient.mp4", "gradient", threads, gradient);
    time_video(dir + "/timing-render.mp4", "render", threads, rendered);
    time_video(dir + "/timing-noise.mp4", "noise", threads, noise);
  }
  time_png(dir + "/timing-gradient.png", "gradient", gradient(0));
  time_png(dir + "/timing-render.png", "render", rendered(0));
  time_png(dir + "/timing-noise.png", "noise", noise(0));
  return 0;
}
