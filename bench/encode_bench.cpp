// H.264 encoder settings against each other on real frames: processor time per frame,
// file size and quality (PSNR of the decoded video against the frames given).
//
//   tissu_encode_bench FRAME_DIR [--fps N] [--presets a,b,...] [--tunes t,...] [--crf N[,N...]]
//                      [--params "k=v:k=v;k=v..."]
//
// FRAME_DIR holds frame_NNNNNN.png files, e.g. from
//   tissu render scenes/demo.json --png --no-mp4 --out /tmp/frames -y
// Each setting encodes every frame on this thread (encoder_threads 1, as tissu does) into a
// temporary MP4; the time is this thread's processor time in Mp4Writer::write_frame and
// finish(), with the RGB to YUV conversion included. --params lists x264 settings to add
// to each preset, separated by ';' ("none": nothing added; default: Mp4Options' own).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "render/cpu_clock.h"
#include "video/image.h"
#include "video/mp4_reader.h"
#include "video/mp4_writer.h"
#include "video/png_io.h"

using namespace tissu;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> split(const std::string& list, char separator = ',') {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, separator)) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: tissu_encode_bench FRAME_DIR [--fps N] [--presets LIST] [--tunes LIST] [--crf LIST] "
                 "[--params LIST]\n");
    return 2;
  }
  const fs::path dir = argv[1];
  int fps = 30;
  std::vector<int> crfs = {20};
  std::vector<std::string> params = {Mp4Options().x264_params};  // what tissu uses
  std::vector<std::string> presets = {"ultrafast", "superfast", "veryfast", "faster", "medium"};
  std::vector<std::string> tunes = {""};
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--fps") fps = std::stoi(v);
    else if (a == "--presets") presets = split(v);
    else if (a == "--tunes") tunes = split(v);
    else if (a == "--crf") {
      crfs.clear();
      for (const std::string& c : split(v)) crfs.push_back(std::stoi(c));
    } else if (a == "--params") params = split(v, ';');
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".png") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Image> frames;
  for (const fs::path& f : files) frames.push_back(read_png(f.string()));
  if (frames.empty()) {
    std::fprintf(stderr, "tissu_encode_bench: no PNG frames in %s\n", dir.c_str());
    return 2;
  }
  std::printf("%zu frames %dx%d\n\n", frames.size(), frames[0].width, frames[0].height);
  std::printf("| preset | tune | x264 settings | CRF | CPU ms/frame | kB per second of video | mean PSNR dB | lowest PSNR dB |\n");
  std::printf("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |\n");
  const fs::path out = fs::temp_directory_path() / "tissu_encode_bench.mp4";
  auto run = [&](const Mp4Options& o) {
    const double c0 = thread_cpu_seconds();
    {
      Mp4Writer writer(out.string(), frames[0].width, frames[0].height, FrameRate(fps), o);
      for (const Image& f : frames) writer.write_frame(f);
      writer.finish();
    }
    const double cpu_ms = 1e3 * (thread_cpu_seconds() - c0) / frames.size();
    const double kb_per_s = fs::file_size(out) / 1e3 / (double(frames.size()) / fps);
    Mp4Reader reader(out.string());
    Image decoded;
    double sum = 0.0, lowest = 1e9;
    size_t k = 0;
    while (reader.read_frame(decoded) && k < frames.size()) {
      const double psnr = compare_images(frames[k++], decoded).psnr_db;
      sum += psnr;
      lowest = std::min(lowest, psnr);
    }
    std::printf("| %s | %s | %s | %d | %.1f | %.0f | %.2f | %.2f |\n", o.preset.c_str(),
                o.tune.empty() ? "none" : o.tune.c_str(), o.x264_params.empty() ? "none" : o.x264_params.c_str(),
                o.crf, cpu_ms, kb_per_s, sum / k, lowest);
    std::fflush(stdout);
  };
  for (const std::string& tune : tunes) {
    for (const std::string& preset : presets) {
      for (const std::string& param : params) {
        for (const int crf : crfs) {
          Mp4Options o;
          o.preset = preset;
          o.tune = tune;
          o.crf = crf;
          o.x264_params = param == "none" ? "" : param;
          run(o);
        }
      }
    }
  }
  fs::remove(out);
  return 0;
}
