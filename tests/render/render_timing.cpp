// Measures how long the renderer takes for one frame of a ~5000-triangle draped
// cloth over a sphere, with a ground, shadow, caption and info text:
//   render_timing [--width W] [--height H] [--msaa 1|2|4] [--frames N] [--png FILE]
//                 [--ground 0|1] [--text 0|1]
// Prints the mean and fastest wall time of draw() + read_rgb(), the CPU time of all
// threads, and a hash of the last frame (the hash lets runs with different
// LP_NUM_THREADS be compared for identical output).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "render/renderer.h"
#include "test_scenes.h"

using Clock = std::chrono::steady_clock;

// CPU time of all threads of the process (llvmpipe rasterizes on worker threads).
double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char** argv) {
  tissu::RenderSettings settings;
  int frames = 20;
  std::string png;
  bool with_ground = true, with_text = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--width") settings.width = std::atoi(value.c_str());
    else if (key == "--height") settings.height = std::atoi(value.c_str());
    else if (key == "--msaa") settings.msaa = std::atoi(value.c_str());
    else if (key == "--frames") frames = std::atoi(value.c_str());
    else if (key == "--png") png = value;
    else if (key == "--ground") with_ground = value != "0";
    else if (key == "--text") with_text = value != "0";
    else {
      std::fprintf(stderr, "render_timing: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  if (with_ground) {
    settings.ground = tissu::Ground{};
    settings.ground->height = -0.9;
  }
  if (with_text) settings.caption = "Cloth draped over a sphere";

  // 50 x 50 squares = 5000 triangles.
  tissu::FrameContent frame = tissu::test::draped_cloth(50, 2.0, 0.5);
  frame.obstacles.push_back(tissu::test::sphere(tissu::Vec3::Zero(), 0.49));
  if (with_text) {
    frame.overlay_lines = tissu::info_overlay_lines("implicit_euler", frame.triangles.size(), 1.25);
  }

  try {
    tissu::Renderer renderer(settings);
    std::vector<uint8_t> image;
    renderer.draw(frame);  // first frame: camera, font atlas, driver warm-up
    renderer.read_rgb(image);
    // llvmpipe defers rasterization until the read-back (or until a buffer in use is
    // rewritten), so only the total of draw() + read_rgb() is a meaningful time.
    double wall_sum = 0, wall_min = 1e300, cpu_sum = 0;
    for (int f = 0; f < frames; ++f) {
      const auto t0 = Clock::now();
      const double c0 = cpu_seconds();
      renderer.draw(frame);
      renderer.read_rgb(image);
      const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
      cpu_sum += cpu_seconds() - c0;
      wall_sum += wall;
      wall_min = std::min(wall_min, wall);
    }
    std::printf("%dx%d msaa %d (samples %d), %zu triangles, %d frames: draw + read back "
                "%.1f ms per frame (fastest %.1f ms), CPU %.1f ms per frame; hash %016llx\n",
                settings.width, settings.height, settings.msaa, renderer.samples(),
                frame.triangles.size(), frames, 1e3 * wall_sum / frames, 1e3 * wall_min,
                1e3 * cpu_sum / frames,
                static_cast<unsigned long long>(tissu::test::image_hash(image)));
    if (!png.empty() && !stbi_write_png(png.c_str(), settings.width, settings.height, 3,
                                        image.data(), settings.width * 3)) {
      std::fprintf(stderr, "render_timing: cannot write %s\n", png.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_timing: %s\n", e.what());
    return 1;
  }
  return 0;
}
