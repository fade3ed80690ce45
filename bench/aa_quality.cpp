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
//
//   tissu_aa_quality --shadow UNSHADOWED.png FINE.png CANDIDATE.png... [--levels N] [--crop ...]
//
// Shadow quality instead: FINE is the same frame with a reference shadow (docs/rendering.md,
// "The ground's shadow", used a 4096-texel shadow map drawn by an earlier build),
// UNSHADOWED without the ground's shadow. For each candidate: the pixels more than N
// levels of 255 (default 4) off FINE in some channel, and the PSNR against FINE over the
// pixels the shadow touches (where FINE or the candidate differs from UNSHADOWED).
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

// Reference first, then each candidate, side by side, the crop's pixels drawn 4x4 each.
void write_crops(const Image& reference, const std::vector<Image>& candidates, int cx, int cy, int cw,
                 int ch, const std::string& path) {
  if (path.empty() || cw <= 0 || ch <= 0) return;
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
  write_png(path, sheet);
}

// Pixels where `a` and `b` differ by more than `levels` in some channel.
long long count_differing(const Image& a, const Image& b, int levels) {
  long long n = 0;
  for (int i = 0; i < a.width * a.height; ++i) n += largest_difference(&a.rgb[3 * i], &b.rgb[3 * i]) > levels;
  return n;
}

void report_shadow(const Image& unshadowed, const Image& fine, const std::vector<Image>& candidates,
                   const std::vector<std::string>& names, int levels) {
  std::printf("| frame | pixels > %d levels off the fine map | %% of the frame | shadowed pixels | PSNR, shadowed pixels (dB) |\n"
              "| --- | ---: | ---: | ---: | ---: |\n",
              levels);
  const int n = fine.width * fine.height;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const Image& c = candidates[k];
    std::vector<bool> shadowed(n);
    long long count = 0;
    for (int i = 0; i < n; ++i) {
      shadowed[i] = largest_difference(&fine.rgb[3 * i], &unshadowed.rgb[3 * i]) > 0 ||
                    largest_difference(&c.rgb[3 * i], &unshadowed.rgb[3 * i]) > 0;
      count += shadowed[i];
    }
    const long long off = count_differing(c, fine, levels);
    std::printf("| %s | %lld | %.4f | %lld | %.2f |\n", names[k].c_str(), off, 100.0 * off / n, count,
                psnr(c, fine, &shadowed));
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int cx = 0, cy = 0, cw = 0, ch = 0;
  std::string crops, unshadowed_file;
  int levels = 4;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--shadow" && i + 1 < argc) {
      unshadowed_file = argv[++i];
    } else if (a == "--levels" && i + 1 < argc) {
      levels = std::stoi(argv[++i]);
    } else if (a == "--crop" && i + 4 < argc) {
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
    std::fprintf(stderr, "usage: tissu_aa_quality REFERENCE_2X.png CANDIDATE.png... [--crop X Y W H] [--out F]\n"
                         "       tissu_aa_quality --shadow UNSHADOWED.png FINE.png CANDIDATE.png... [--levels N] [--crop X Y W H] [--out F]\n");
    return 2;
  }
  const bool shadow = !unshadowed_file.empty();
  const Image reference = shadow ? read_png(files[0]) : half_size(read_png(files[0]));
  std::vector<Image> candidates;
  for (size_t k = 1; k < files.size(); ++k) candidates.push_back(read_png(files[k]));
  if (shadow) {
    report_shadow(read_png(unshadowed_file), reference, candidates, {files.begin() + 1, files.end()}, levels);
    write_crops(reference, candidates, cx, cy, cw, ch, crops);
    return 0;
  }
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
  write_crops(reference, candidates, cx, cy, cw, ch, crops);
  return 0;
}
