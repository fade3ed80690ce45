// tissu compare: compares two PNG files, two directories of PNG frames or two MP4 files
// frame by frame with the golden-frame tests' tolerance, and says which frames differ.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/commands.h"
#include "app/frame_pairs.h"
#include "core/error.h"
#include "video/image.h"
#include "video/png_io.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const char* kUsage =
    "usage: tissu compare A B [--threshold N] [--tolerance F] [--diff DIR]\n"
    "Compares two PNG files, two directories of PNG frames (paired by file name) or two\n"
    "MP4 files (paired by position), and prints per frame the PSNR and the share of pixels\n"
    "over the threshold. A frame matches when at most F of its pixels differ by more than N\n"
    "(of 255) in some channel and the mean channel difference is under 1: the rule of the\n"
    "golden-frame tests. A frame on one side only, or of another size, is a difference.\n"
    "  --threshold N   channel difference a pixel may have, 0 to 255 (default 8)\n"
    "  --tolerance F   fraction of pixels allowed over the threshold, 0 to 1 (default 0.005)\n"
    "  --diff DIR      write DIR/<frame>.diff.png, |A - B| x 8, for every frame that differs\n"
    "Exit codes: 0 every frame within tolerance, 1 a difference beyond tolerance,\n"
    "2 bad usage, unreadable input or a difference image that cannot be written.\n";

struct CompareOptions {
  std::string a, b;
  FrameTolerance tolerance;
  std::string diff_dir;  // empty: no difference images
};

double parse_fraction(const std::string& option, const std::string& text) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && value >= 0 && value <= 1) return value;
  } catch (const std::exception&) {
  }
  throw InputError(option + ": expected a number from 0 to 1, got \"" + text + "\"");
}

bool parse_options(const std::vector<std::string>& args, CompareOptions& o) {
  std::vector<std::string> inputs;
  const bool go = walk_arguments(args, "tissu compare", kUsage,
                                 [&](const std::string& a, const OptionValue& value) {
                                   if (a == "--threshold") {
                                     o.tolerance.threshold =
                                         static_cast<int>(parse_count("--threshold", value(), 0, 255));
                                   } else if (a == "--tolerance") {
                                     o.tolerance.max_fraction_over = parse_fraction("--tolerance", value());
                                   } else if (a == "--diff") {
                                     o.diff_dir = value();
                                   } else if (a.empty() || a[0] != '-') {
                                     if (inputs.size() == 2) return false;
                                     inputs.push_back(a);
                                   } else {
                                     return false;
                                   }
                                   return true;
                                 });
  if (!go) return false;
  if (inputs.size() != 2) {
    throw InputError("tissu compare: expected two inputs A and B (see tissu compare --help)");
  }
  o.a = inputs[0];
  o.b = inputs[1];
  return true;
}

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

std::string measures_text(const ImageDiff& diff, int threshold) {
  char text[160];
  if (std::isinf(diff.psnr_db)) {
    std::snprintf(text, sizeof text, "PSNR inf dB");
  } else {
    std::snprintf(text, sizeof text, "PSNR %.2f dB", diff.psnr_db);
  }
  char rest[160];
  std::snprintf(rest, sizeof rest, ", %.3f%% of pixels over %d, mean difference %.2f",
                100 * diff.fraction_over_threshold, threshold, diff.mean_abs_diff);
  return std::string(text) + rest;
}

// Compares one pair; prints its line and returns whether it is within tolerance.
bool compare_pair(const FramePair& pair, const CompareOptions& o) {
  std::string line = pair.name + ": ";
  std::string diff_path;
  bool ok = false;
  if (!pair.a || !pair.b) {
    line += "only in " + (pair.a ? o.a : o.b);
  } else if (pair.a->width != pair.b->width || pair.a->height != pair.b->height) {
    line += size_text(*pair.a) + " in " + o.a + ", " + size_text(*pair.b) + " in " + o.b;
  } else {
    const ImageDiff diff = compare_images(*pair.a, *pair.b, o.tolerance.threshold);
    ok = o.tolerance.accepts(diff);
    line += measures_text(diff, o.tolerance.threshold);
    if (!ok && !o.diff_dir.empty()) {
      diff_path = (fs::path(o.diff_dir) / (pair.stem + ".diff.png")).string();
      write_png(diff_path, difference_image(*pair.a, *pair.b));
    }
  }
  std::cout << line << (ok ? ": ok" : ": DIFFERS");
  if (!diff_path.empty()) std::cout << ", difference image " << diff_path;
  std::cout << std::endl;
  return ok;
}

std::string count_of_frames(long long n) { return std::to_string(n) + (n == 1 ? " frame" : " frames"); }

// "17 frames compared, all within tolerance" or "2 of 17 frames differ beyond tolerance: ..."
std::string summary(long long frames, const std::vector<std::string>& differing) {
  constexpr std::size_t kNamesShown = 20;
  if (differing.empty()) {
    return count_of_frames(frames) + " compared, " + (frames == 1 ? "within" : "all within") +
           " tolerance";
  }
  std::string text = std::to_string(differing.size()) + " of " + count_of_frames(frames) +
                     (differing.size() == 1 ? " differs" : " differ") + " beyond tolerance: ";
  for (std::size_t i = 0; i < differing.size() && i < kNamesShown; ++i) {
    text += (i ? ", " : "") + differing[i];
  }
  if (differing.size() > kNamesShown) {
    text += " and " + std::to_string(differing.size() - kNamesShown) + " more";
  }
  return text;
}

int compare(const CompareOptions& o) {
  const std::unique_ptr<FramePairs> pairs = open_frame_pairs(o.a, o.b);
  OutputDirs diff_dirs;
  if (!o.diff_dir.empty()) diff_dirs.prepare(o.diff_dir);
  try {
    long long frames = 0, frames_a = 0, frames_b = 0;
    std::vector<std::string> differing;
    for (FramePair pair; pairs->next(pair);) {
      ++frames;
      frames_a += pair.a.has_value();
      frames_b += pair.b.has_value();
      if (!compare_pair(pair, o)) differing.push_back(pair.name);
    }
    if (frames_a != frames_b) {
      std::cout << o.a << " has " << count_of_frames(frames_a) << ", " << o.b << " has " << frames_b
                << "\n";
    }
    std::cout << summary(frames, differing) << std::endl;
    diff_dirs.remove_created_if_empty();
    return differing.empty() ? kExitOk : kExitDifferent;
  } catch (...) {
    diff_dirs.remove_created_if_empty();
    throw;
  }
}

}  // namespace

int command_compare(const std::vector<std::string>& args) {
  CompareOptions options;
  if (!parse_options(args, options)) return kExitOk;
  try {
    return compare(options);
  } catch (const OutputError& e) {
    // A difference image that cannot be written leaves the comparison unfinished.
    std::cerr << "tissu: " << e.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace tissu
