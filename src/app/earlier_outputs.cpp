#include "app/earlier_outputs.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/output_target.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const char* kOverwriteHint = "use -y (--overwrite) to replace ";

// "frame_" + digits + extension: the names Tissu gives frames and snapshots.
bool is_frame_name(const std::string& name, const std::string& extension) {
  const std::string prefix = "frame_";
  if (name.size() <= prefix.size() + extension.size()) return false;
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  if (name.compare(name.size() - extension.size(), extension.size(), extension) != 0) return false;
  return std::all_of(name.begin() + prefix.size(), name.end() - extension.size(),
                     [](unsigned char c) { return std::isdigit(c) != 0; });
}

// The entries of `dir` (a missing directory has none) that `wanted` picks, sorted.
template <typename Wanted>
std::vector<std::string> entries_of(const std::string& dir, const Wanted& wanted) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return out;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (wanted(name)) out.push_back((fs::path(dir) / name).string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool exists_at(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

// "16 frame_*.png", "3 frame_*.obj and final.obj".
std::string describe(const std::vector<std::string>& files) {
  long long png = 0, obj = 0;
  bool final_obj = false;
  for (const std::string& f : files) {
    const std::string name = fs::path(f).filename().string();
    if (name == "final.obj") {
      final_obj = true;
    } else if (is_frame_name(name, ".png")) {
      ++png;
    } else {
      ++obj;
    }
  }
  std::vector<std::string> parts;
  if (png > 0) parts.push_back(std::to_string(png) + " frame_*.png");
  if (obj > 0) parts.push_back(std::to_string(obj) + " frame_*.obj");
  if (final_obj) parts.push_back("final.obj");
  std::string text;
  for (const std::string& p : parts) text += (text.empty() ? "" : " and ") + p;
  return text;
}

}  // namespace

EarlierOutputs::EarlierOutputs(const RunOutputPaths& paths) {
  auto add_file = [&](const std::string& path) {
    if (!path.empty() && exists_at(path)) found_.push_back({path, false, {path}});
  };
  auto add_dir = [&](const std::string& dir, const std::vector<std::string>& files) {
    if (!files.empty()) found_.push_back({dir, true, files});
  };
  auto pngs = [](const std::string& name) { return is_frame_name(name, ".png"); };
  auto objs = [](const std::string& name) {
    return name == "final.obj" || is_frame_name(name, ".obj");
  };
  add_file(paths.mp4);
  if (!paths.png_dir.empty()) add_dir(paths.png_dir, entries_of(paths.png_dir, pngs));
  if (!paths.stills_dir.empty()) add_dir(paths.stills_dir, entries_of(paths.stills_dir, pngs));
  if (!paths.obj_dir.empty()) add_dir(paths.obj_dir, entries_of(paths.obj_dir, objs));
  add_file(paths.report);
  for (const Kind& kind : found_) {
    for (const std::string& f : kind.files) check_output_target(f);
  }
}

void EarlierOutputs::refuse() const {
  if (found_.empty()) return;
  const Kind& first = found_.front();
  if (!first.directory) {
    throw OutputError(first.place + ": already exists; " + kOverwriteHint + "it");
  }
  throw OutputError(first.place + ": holds frames of an earlier run (" + describe(first.files) +
                    "); " + kOverwriteHint + "them");
}

void EarlierOutputs::remove() const {
  for (const Kind& kind : found_) {
    for (const std::string& f : kind.files) {
      std::error_code ec;
      fs::remove(f, ec);
      if (ec) throw OutputError(f + ": cannot remove the earlier run's file: " + ec.message());
    }
  }
}

}  // namespace tissu
