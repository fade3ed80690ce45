#include "app/frame_pairs.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <set>
#include <vector>

#include "core/error.h"
#include "video/mp4_reader.h"
#include "video/png_io.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

enum class InputKind { png, directory, video };

const char* kind_name(InputKind kind) {
  switch (kind) {
    case InputKind::png: return "a PNG file";
    case InputKind::directory: return "a directory";
    case InputKind::video: return "an MP4 file";
  }
  return "";
}

std::string lower_extension(const fs::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

InputKind kind_of(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw InputError(path + ": cannot read: " +
                     (ec ? ec.message() : std::string("No such file or directory")));
  }
  if (fs::is_directory(status)) return InputKind::directory;
  const std::string extension = lower_extension(path);
  if (extension == ".png") return InputKind::png;
  if (extension == ".mp4") return InputKind::video;
  throw InputError(path + ": not a PNG file, an MP4 file or a directory of PNG frames");
}

// Two PNG files: one pair, named after the first.
class PngFilePair : public FramePairs {
 public:
  PngFilePair(std::string a, std::string b) : a_(std::move(a)), b_(std::move(b)) {}

  bool next(FramePair& pair) override {
    if (done_) return false;
    done_ = true;
    pair.name = fs::path(a_).filename().string();
    pair.stem = fs::path(a_).stem().string();
    pair.a = read_png(a_);
    pair.b = read_png(b_);
    return true;
  }

 private:
  std::string a_, b_;
  bool done_ = false;
};

// The names of the PNG files in `dir`, sorted; InputError when there are none.
std::set<std::string> png_names(const std::string& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code ignored;  // an entry that cannot be examined is read, and named, later
    if (lower_extension(it->path()) == ".png" && !it->is_directory(ignored)) {
      names.insert(it->path().filename().string());
    }
  }
  if (ec) throw InputError(dir + ": cannot list directory: " + ec.message());
  if (names.empty()) throw InputError(dir + ": no PNG frames in directory");
  return names;
}

// Two directories of PNG frames, paired by file name.
class DirectoryPairs : public FramePairs {
 public:
  DirectoryPairs(std::string a, std::string b) : a_(std::move(a)), b_(std::move(b)) {
    const std::set<std::string> in_a = png_names(a_), in_b = png_names(b_);
    std::set<std::string> all = in_a;
    all.insert(in_b.begin(), in_b.end());
    for (const std::string& name : all) frames_.push_back({name, in_a.count(name) > 0, in_b.count(name) > 0});
  }

  bool next(FramePair& pair) override {
    if (next_ == frames_.size()) return false;
    const Frame& frame = frames_[next_++];
    pair.name = frame.name;
    pair.stem = fs::path(frame.name).stem().string();
    pair.a.reset();
    pair.b.reset();
    if (frame.in_a) pair.a = read_png((fs::path(a_) / frame.name).string());
    if (frame.in_b) pair.b = read_png((fs::path(b_) / frame.name).string());
    return true;
  }

 private:
  struct Frame {
    std::string name;
    bool in_a, in_b;
  };
  std::string a_, b_;
  std::vector<Frame> frames_;
  std::size_t next_ = 0;
};

// Two videos, paired by position: frame 0 with frame 0, and so on.
class VideoPairs : public FramePairs {
 public:
  VideoPairs(const std::string& a, const std::string& b) : a_(a), b_(b) {}

  bool next(FramePair& pair) override {
    pair.a.reset();
    pair.b.reset();
    Image frame;
    if (a_.read_frame(frame)) pair.a = std::move(frame);
    if (b_.read_frame(frame)) pair.b = std::move(frame);
    if (!pair.a && !pair.b) return false;
    const long long index = next_index_++;
    char stem[32];
    std::snprintf(stem, sizeof stem, "frame_%06lld", index);
    pair.name = "frame " + std::to_string(index);
    pair.stem = stem;
    return true;
  }

 private:
  Mp4Reader a_, b_;
  long long next_index_ = 0;
};

}  // namespace

std::unique_ptr<FramePairs> open_frame_pairs(const std::string& a, const std::string& b) {
  const InputKind kind = kind_of(a);
  const InputKind kind_b = kind_of(b);
  if (kind != kind_b) {
    throw InputError("tissu compare: " + a + " is " + kind_name(kind) + " but " + b + " is " +
                     kind_name(kind_b) +
                     "; compare two PNG files, two directories of PNG frames or two MP4 files");
  }
  switch (kind) {
    case InputKind::png: return std::make_unique<PngFilePair>(a, b);
    case InputKind::directory: return std::make_unique<DirectoryPairs>(a, b);
    case InputKind::video: return std::make_unique<VideoPairs>(a, b);
  }
  return nullptr;
}

}  // namespace tissu
