// Anti-aliasing quality against a 16-sample reference: PSNR of each candidate frame, over
// the whole frame and over the edge pixels (where a single-sample frame differs most from
// the reference), and a side-by-side crop, magnified, to look at.
//
//   tissu_aa_quality REFERENCE_2X.png CANDIDATE.png... [--crop X Y W H] [--out CROPS.png]
//
// Also times render/image/fxaa.h on the first candidate (processor time of this thread, best of
// 20 runs) and counts the pixels it changes.
//
// REFERENCE_2X is the same frame drawn at twice the width and height with MSAA 4; each
// 2x2 block averages to one pixel (16 samples). The first candidate should be the
// single-sample frame: its differences from the reference pick the edge pixels.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/cpu_clock.h"
#include "render/image/fxaa.h"
#include "video/image.h"
#include "video/png_io.h"

using namespace tissu;

namespace {

Image half_size(const Image& big) {
  Image out(big.width / 2, big.height / 2);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const int sum = big.pixel(2 * x, 2 * y)[c] + big.pixel(2 * x + 1, 2 * y)[c] +
                        big.pixel(2 * x, 2 * y + 1)[c] + big.pixel(2 * x + 1, 2 * y + 1)[c];
        out.pixel(x, y)[c] = static_cast<uint8_t>((sum + 2) / 4);
      }
    }
  }
  return out;
}

int largest_difference(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a[c]) - int(b[c])));
  return d;
}

double psnr(const Image& a, const Image& b, const std::vector<bool>* mask) {
  double sum = 0.0;
  long long n = 0;
  for (int i = 0; i < a.width * a.height; ++i) {
    if (mask && !(*mask)[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = double(a.rgb[3 * i + c]) - double(b.rgb[3 * i + c]);
      sum += d * d;
    }
    n += 3;
  }
  if (n == 0 || sum == 0.0) return INFINITY;
  return 10.0 * std::log10(255.0 * 255.0 / (sum / n));
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int cx = 0, cy = 0, cw = 0, ch = 0;
  std::string crops;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--crop" && i + 4 < argc) {
      cx = std::stoi(argv[++i]);
      cy = std::stoi(argv[++i]);
      cw = std::stoi(argv[++i]);
      ch = std::stoi(argv[++i]);
    } else if (a == "--out" && i + 1 < argc) {
      crops = argv[++i];
    } else {
      files.push_back(a);
    }
  }
  if (files.size() < 2) {
    std::fprintf(stderr, "usage: tissu_aa_quality REFERENCE_2X.png CANDIDATE.png... [--crop X Y W H] [--out F]\n");
    return 2;
  }
  const Image reference = half_size(read_png(files[0]));
  std::vector<Image> candidates;
  for (size_t k = 1; k < files.size(); ++k) candidates.push_back(read_png(files[k]));
  std::vector<bool> edges(reference.width * reference.height, false);
  long long edge_count = 0;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      if (largest_difference(candidates[0].pixel(x, y), reference.pixel(x, y)) > 8) {
        edges[y * reference.width + x] = true;
        ++edge_count;
      }
    }
  }
  std::printf("reference %s (2x2 blocks of MSAA 4: 16 samples); %lld edge pixels (%.2f%%)\n\n",
              files[0].c_str(), edge_count, 100.0 * edge_count / (reference.width * reference.height));
  std::printf("| frame | PSNR, whole frame (dB) | PSNR, edge pixels (dB) |\n| --- | ---: | ---: |\n");
  for (size_t k = 0; k < candidates.size(); ++k) {
    std::printf("| %s | %.2f | %.2f |\n", files[k + 1].c_str(), psnr(candidates[k], reference, nullptr),
                psnr(candidates[k], reference, &edges));
  }
  {
    FxaaScratch scratch;
    double best = 1e9;
    long long changed = 0;
    for (int run = 0; run < 20; ++run) {
      std::vector<uint8_t> rgb = candidates[0].rgb;
      const double c0 = thread_cpu_seconds();
      fxaa_rgb(rgb, candidates[0].width, candidates[0].height, scratch);
      best = std::min(best, thread_cpu_seconds() - c0);
      changed = 0;
      for (size_t i = 0; i < rgb.size(); i += 3) changed += rgb[i] != candidates[0].rgb[i] || rgb[i + 1] != candidates[0].rgb[i + 1] || rgb[i + 2] != candidates[0].rgb[i + 2];
    }
    std::printf("\nfxaa_rgb on %s: %.2f ms (best of 20, processor time), %lld pixels changed (%.2f%%)\n",
                files[1].c_str(), 1e3 * best, changed, 100.0 * changed / (candidates[0].width * candidates[0].height));
  }
  if (!crops.empty() && cw > 0 && ch > 0) {
    // Reference first, then each candidate, side by side, each pixel drawn 4x4.
    const int zoom = 4, gap = 8;
    std::vector<const Image*> shown = {&reference};
    for (const Image& c : candidates) shown.push_back(&c);
    Image sheet(int(shown.size()) * (cw * zoom + gap) - gap, ch * zoom);
    std::fill(sheet.rgb.begin(), sheet.rgb.end(), 255);
    for (size_t k = 0; k < shown.size(); ++k) {
      for (int y = 0; y < ch * zoom; ++y) {
        for (int x = 0; x < cw * zoom; ++x) {
          const uint8_t* p = shown[k]->pixel(cx + x / zoom, cy + y / zoom);
          std::copy(p, p + 3, sheet.pixel(int(k) * (cw * zoom + gap) + x, y));
        }
      }
    }
    write_png(crops, sheet);
  }
  return 0;
}
