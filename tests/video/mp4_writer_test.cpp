#include "video/mp4_writer.h"

#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <fstream>

#include "core/error.h"
#include "video_test_support.h"

namespace tissu {
namespace {

using test::ScratchDir;

void write_gradient_video(const std::string& path, int width, int height, int frames, FrameRate fps = 30) {
  Mp4Writer writer(path, width, height, fps);
  for (int i = 0; i < frames; ++i) writer.write_frame(test::moving_gradient(width, height, i));
  writer.finish();
}

template <typename Error, typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(Mp4Writer, WritesBrowserFriendlyH264) {
  ScratchDir dir;
  const std::string path = dir.file("gradient.mp4");
  write_gradient_video(path, 320, 240, 30);

  const test::VideoFacts video = test::read_video(path);
  EXPECT_EQ(video.codec, "h264");
  EXPECT_EQ(video.pixel_format, "yuv420p");
  EXPECT_EQ(video.width, 320);
  EXPECT_EQ(video.height, 240);
  EXPECT_EQ(double(video.fps_num) / video.fps_den, 30.0);
  EXPECT_EQ(video.frames_in_index, 30);
  EXPECT_EQ(video.frames.size(), 30u);

  // faststart: the index ('moov') precedes the samples ('mdat'), so playback can start early.
  const std::vector<std::string> boxes = test::top_level_boxes(path);
  const auto moov = std::find(boxes.begin(), boxes.end(), "moov");
  const auto mdat = std::find(boxes.begin(), boxes.end(), "mdat");
  ASSERT_NE(moov, boxes.end());
  ASSERT_NE(mdat, boxes.end());
  EXPECT_LT(moov - boxes.begin(), mdat - boxes.begin());
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"gradient.mp4"});  // no temporary file left
}

// CRF 20 on these gradients, measured: mean difference 1.1 of 255 and largest 8 in the worst
// frame. Tolerance: mean < 2 and under 1% of pixels off by more than 8. Encoding with BT.601
// coefficients while the stream says BT.709 gives mean 7.1 with 66% of pixels over 8.
TEST(Mp4Writer, DecodedFramesMatchTheInput) {
  ScratchDir dir;
  const std::string path = dir.file("gradient.mp4");
  write_gradient_video(path, 320, 240, 30);

  const test::VideoFacts video = test::read_video(path);
  ASSERT_EQ(video.frames.size(), 30u);
  for (int i = 0; i < 30; ++i) {
    const ImageDiff diff = compare_images(video.frames[i], test::moving_gradient(320, 240, i), 8);
    EXPECT_LT(diff.mean_abs_diff, 2.0) << "frame " << i;
    EXPECT_LT(diff.fraction_over_threshold, 0.01) << "frame " << i;
  }
}

TEST(Mp4Writer, FractionalFrameRates) {
  ScratchDir dir;
  write_gradient_video(dir.file("ntsc.mp4"), 64, 48, 10, FrameRate(30000, 1001));
  const test::VideoFacts ntsc = test::read_video(dir.file("ntsc.mp4"));
  EXPECT_EQ(ntsc.fps_num * 1001, ntsc.fps_den * 30000);

  write_gradient_video(dir.file("pal.mp4"), 64, 48, 10, FrameRate(25.0));
  const test::VideoFacts pal = test::read_video(dir.file("pal.mp4"));
  EXPECT_EQ(pal.fps_num, pal.fps_den * 25);
}

TEST(Mp4Writer, FinishAfterSomeFramesKeepsThem) {
  ScratchDir dir;
  const std::string path = dir.file("short.mp4");
  Mp4Writer writer(path, 320, 240, 30);
  for (int i = 0; i < 5; ++i) writer.write_frame(test::moving_gradient(320, 240, i));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{".short.mp4.partial"});
  writer.finish();
  EXPECT_FALSE(writer.is_open());

  const test::VideoFacts video = test::read_video(path);
  EXPECT_EQ(video.frames_in_index, 5);
  ASSERT_EQ(video.frames.size(), 5u);
  EXPECT_LT(compare_images(video.frames[4], test::moving_gradient(320, 240, 4)).mean_abs_diff, 2.0);
}

TEST(Mp4Writer, FinishWithoutFramesLeavesNoFile) {
  ScratchDir dir;
  const std::string path = dir.file("empty.mp4");
  Mp4Writer writer(path, 320, 240, 30);
  EXPECT_EQ(error_of<OutputError>([&] { writer.finish(); }), path + ": no frames to write");
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Mp4Writer, AbortLeavesNoFile) {
  ScratchDir dir;
  Mp4Writer writer(dir.file("aborted.mp4"), 320, 240, 30);
  for (int i = 0; i < 3; ++i) writer.write_frame(test::moving_gradient(320, 240, i));
  writer.abort();
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_THROW(writer.write_frame(test::moving_gradient(320, 240, 3)), std::logic_error);
}

TEST(Mp4Writer, DestructionWithoutFinishLeavesNoFile) {
  ScratchDir dir;
  {
    Mp4Writer writer(dir.file("dropped.mp4"), 320, 240, 30);
    writer.write_frame(test::moving_gradient(320, 240, 0));
    EXPECT_FALSE(dir.entries().empty());
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Mp4Writer, MissingDirectoryIsAnOutputErrorNamingThePath) {
  ScratchDir dir;
  const std::string path = dir.file("no-such-dir/out.mp4");
  const std::string message = error_of<OutputError>([&] { Mp4Writer(path, 320, 240, 30); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_TRUE(dir.entries().empty());
}

// /sys refuses new files even to root (these tests run as root, so a chmod'ed directory
// would not be read-only).
TEST(Mp4Writer, ReadOnlyDirectoryIsAnOutputErrorNamingThePath) {
  const std::string path = "/sys/tissu-video-test.mp4";
  const std::string message = error_of<OutputError>([&] { Mp4Writer(path, 320, 240, 30); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
  std::ifstream leftover("/sys/.tissu-video-test.mp4.partial");
  EXPECT_FALSE(leftover.good());
}

TEST(Mp4Writer, PathThroughAFileIsAnOutputError) {
  ScratchDir dir;
  std::ofstream(dir.file("plain-file")) << "x";
  const std::string path = dir.file("plain-file/out.mp4");
  const std::string message = error_of<OutputError>([&] { Mp4Writer(path, 320, 240, 30); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain-file"});
}

TEST(Mp4Writer, ColonInFileNameIsNotAProtocol) {
  ScratchDir dir;
  write_gradient_video(dir.file("run:1.mp4"), 64, 48, 3);
  EXPECT_EQ(test::read_video(dir.file("run:1.mp4")).frames.size(), 3u);
}

// A full disk is simulated with a file size limit (RLIMIT_FSIZE): writes past it fail with
// EFBIG ("File too large") just as they fail with ENOSPC on a full disk.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    saved_handler_ = std::signal(SIGXFSZ, SIG_IGN);  // report EFBIG instead of killing the process
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, saved_handler_);
  }

 private:
  rlimit saved_{};
  void (*saved_handler_)(int) = nullptr;
};

TEST(Mp4Writer, FullDiskIsAnOutputErrorAndLeavesNoFile) {
  ScratchDir dir;
  const std::string path = dir.file("full.mp4");
  std::string message;
  {
    FileSizeLimit limit(64 * 1024);
    message = error_of<OutputError>([&] {
      Mp4Writer writer(path, 320, 240, 30);
      for (unsigned i = 0; i < 30; ++i) writer.write_frame(test::noise_image(320, 240, i));
      writer.finish();
    });
  }
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Mp4Writer, FullDiskWhileFinishingLeavesNoFile) {
  ScratchDir dir;
  const std::string path = dir.file("full.mp4");
  Mp4Writer writer(path, 320, 240, 30);
  for (unsigned i = 0; i < 3; ++i) writer.write_frame(test::noise_image(320, 240, i));
  std::string message;
  {
    FileSizeLimit limit(1024);  // the encoder still holds frames; flushing them must fail
    message = error_of<OutputError>([&] { writer.finish(); });
  }
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_FALSE(writer.is_open());
}

// /dev/full fails every write with ENOSPC, like a full disk. The writer creates its
// temporary file in the target's directory, so a symlink there with that name leads to it.
TEST(Mp4Writer, NoSpaceLeftIsAnOutputErrorAndLeavesNoFile) {
  ScratchDir dir;
  const std::string path = dir.file("full.mp4");
  ASSERT_EQ(symlink("/dev/full", dir.file(".full.mp4.partial").c_str()), 0);
  const std::string message = error_of<OutputError>([&] {
    Mp4Writer writer(path, 320, 240, 30);
    for (unsigned i = 0; i < 10; ++i) writer.write_frame(test::noise_image(320, 240, i));
    writer.finish();
  });
  EXPECT_NE(message.find(path + ": "), std::string::npos) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Mp4Writer, SameFramesGiveIdenticalBytes) {
  ScratchDir dir;
  write_gradient_video(dir.file("a.mp4"), 320, 240, 30);
  write_gradient_video(dir.file("b.mp4"), 320, 240, 30);
  const std::vector<char> a = test::file_bytes(dir.file("a.mp4"));
  const std::vector<char> b = test::file_bytes(dir.file("b.mp4"));
  EXPECT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b) << "sizes " << a.size() << " and " << b.size();
}

// Whatever the memory the encoder is given held before must not change the video: glibc
// fills each new allocation with a different byte here (M_PERTURB), so an encoder that reads
// memory it never wrote gives different bytes. (x264's AVX-512 code did, on processors that
// have it.)
TEST(Mp4Writer, StaleMemoryDoesNotChangeTheVideo) {
  ScratchDir dir;
  std::vector<char> first;
  for (int fill : {0x01, 0x55, 0xAA}) {
    const std::string path = dir.file("fill" + std::to_string(fill) + ".mp4");
    ASSERT_EQ(mallopt(M_PERTURB, fill), 1);
    write_gradient_video(path, 320, 240, 30);
    mallopt(M_PERTURB, 0);
    if (first.empty()) {
      first = test::file_bytes(path);
    } else {
      EXPECT_TRUE(test::file_bytes(path) == first) << "allocations filled with " << fill;
    }
  }
}

// Two runs within the same second would share a wall-clock creation time, so the byte
// comparison alone cannot catch one: check that the headers that can hold it hold zero.
TEST(Mp4Writer, HeadersCarryNoCreationTime) {
  ScratchDir dir;
  write_gradient_video(dir.file("a.mp4"), 64, 48, 3);
  const std::vector<char> bytes = test::file_bytes(dir.file("a.mp4"));
  const std::string text(bytes.begin(), bytes.end());
  for (const char* box : {"mvhd", "tkhd", "mdhd"}) {
    const std::size_t at = text.find(box);
    ASSERT_NE(at, std::string::npos) << box;
    const bool wide = text[at + 4] == 1;                              // version 1: 64-bit times
    const std::size_t times_at = at + 8, times_size = wide ? 16 : 8;  // creation + modification
    ASSERT_LE(times_at + times_size, text.size());
    EXPECT_EQ(text.substr(times_at, times_size), std::string(times_size, '\0')) << box;
  }
}

TEST(Mp4Writer, OddSizesArePaddedByRepeatingTheEdge) {
  ScratchDir dir;
  const std::string path = dir.file("odd.mp4");
  Image frame(63, 47);
  for (int y = 0; y < 47; ++y) {
    for (int x = 0; x < 63; ++x) {
      std::uint8_t* p = frame.pixel(x, y);
      p[0] = 200, p[1] = std::uint8_t(x * 4), p[2] = std::uint8_t(y * 5);
    }
  }
  Mp4Writer writer(path, 63, 47, 30);
  EXPECT_EQ(writer.video_width(), 64);
  EXPECT_EQ(writer.video_height(), 48);
  writer.write_frame(frame);
  writer.finish();

  const test::VideoFacts video = test::read_video(path);
  EXPECT_EQ(video.width, 64);
  EXPECT_EQ(video.height, 48);
  ASSERT_EQ(video.frames.size(), 1u);
  const Image& decoded = video.frames[0];
  for (int y = 0; y < 47; ++y) {  // the added column repeats the last one
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(decoded.pixel(63, y)[c], frame.pixel(62, y)[c], 12) << y;
  }
}

TEST(Mp4Writer, RejectsBadSizesAndRates) {
  ScratchDir dir;
  const std::string path = dir.file("bad.mp4");
  EXPECT_EQ(error_of<InputError>([&] { Mp4Writer(path, 0, 240, 30); }),
            path + ": video size must be positive, got 0x240");
  EXPECT_EQ(error_of<InputError>([&] { Mp4Writer(path, 320, 240, FrameRate(0.0)); }),
            path + ": frame rate must be positive, got 0/1");
  Mp4Writer writer(path, 320, 240, 30);
  EXPECT_THROW(writer.write_frame(Image(320, 200)), std::invalid_argument);
}

TEST(FrameRate, ConvertsDecimalRates) {
  const FrameRate rate(29.97);
  EXPECT_EQ(rate.num * 100, rate.den * 2997);
  EXPECT_EQ(FrameRate(24.0).num, 24);
  EXPECT_EQ(FrameRate(24.0).den, 1);
}

}  // namespace
}  // namespace tissu
