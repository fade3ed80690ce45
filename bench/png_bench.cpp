// PNG writing settings against each other on real frames: processor time per frame and
// file size of the writer Tissu uses (encode_png: ISA-L's igzip) and, through libpng, of
// zlib levels, strategies and row filters (docs/performance.md).
//
//   tissu_png_bench FRAME_DIR
//
// FRAME_DIR holds frame_NNNNNN.png files, e.g. from
//   tissu render scenes/demo.json --png --no-mp4 --out /tmp/frames -y
// Each setting compresses every frame into memory on this thread (best of 3 passes); the
// first row is what video/png_write.cpp writes.
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "render/cpu_clock.h"
#include "video/image.h"
#include "video/png_io.h"

using namespace tissu;
namespace fs = std::filesystem;

namespace {

void append(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}
void flush(png_structp) {}

struct Setting {
  const char* name;
  int level, filter, strategy;
};

std::size_t compress(const Image& image, const Setting& s) {
  std::vector<unsigned char> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(png, &out, append, flush);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, s.level);
  png_set_compression_strategy(png, s.strategy);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, s.filter);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    png_write_row(png, const_cast<png_bytep>(&image.rgb[std::size_t(y) * image.width * 3]));
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out.size();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: tissu_png_bench FRAME_DIR\n");
    return 2;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(argv[1])) {
    if (e.path().extension() == ".png") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Image> frames;
  for (const fs::path& f : files) frames.push_back(read_png(f.string()));
  if (frames.empty()) {
    std::fprintf(stderr, "tissu_png_bench: no PNG frames in %s\n", argv[1]);
    return 2;
  }
  const Setting settings[] = {
      {"zlib level 1, up (before)", 1, PNG_FILTER_UP, Z_DEFAULT_STRATEGY},
      {"level 1, none", 1, PNG_FILTER_NONE, Z_DEFAULT_STRATEGY},
      {"level 1, sub", 1, PNG_FILTER_SUB, Z_DEFAULT_STRATEGY},
      {"level 1, paeth", 1, PNG_FILTER_PAETH, Z_DEFAULT_STRATEGY},
      {"level 1, up, RLE", 1, PNG_FILTER_UP, Z_RLE},
      {"level 1, sub, RLE", 1, PNG_FILTER_SUB, Z_RLE},
      {"level 1, paeth, RLE", 1, PNG_FILTER_PAETH, Z_RLE},
      {"level 1, up, Huffman only", 1, PNG_FILTER_UP, Z_HUFFMAN_ONLY},
      {"level 0 (stored), none", 0, PNG_FILTER_NONE, Z_DEFAULT_STRATEGY},
      {"level 3, up", 3, PNG_FILTER_UP, Z_DEFAULT_STRATEGY},
      {"level 6, up", 6, PNG_FILTER_UP, Z_DEFAULT_STRATEGY},
  };
  std::printf("%zu frames %dx%d, zlib %s\n\n", frames.size(), frames[0].width, frames[0].height, zlibVersion());
  std::printf("| setting | CPU ms/frame | kB/frame |\n| --- | ---: | ---: |\n");
  auto report = [&](const char* name, auto&& encode) {
    double best = 1e30;
    std::size_t bytes = 0;
    for (int pass = 0; pass < 3; ++pass) {
      bytes = 0;
      const double c0 = thread_cpu_seconds();
      for (const Image& f : frames) bytes += encode(f);
      best = std::min(best, thread_cpu_seconds() - c0);
    }
    std::printf("| %s | %.1f | %.0f |\n", name, 1e3 * best / frames.size(), bytes / 1e3 / frames.size());
    std::fflush(stdout);
  };
  report("ISA-L igzip level 1, up (used: encode_png)",
         [](const Image& f) { return encode_png(f.rgb.data(), f.width, f.height).size(); });
  for (const Setting& s : settings) {
    report(s.name, [&](const Image& f) { return compress(f, s); });
  }
  return 0;
}
