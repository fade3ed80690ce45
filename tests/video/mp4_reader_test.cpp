#include "video/mp4_reader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "core/error.h"
#include "video/mp4_writer.h"
#include "video_test_support.h"

namespace tissu {
namespace {

using test::ScratchDir;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

// Every frame comes back, in order, as the independent reader of the tests decodes it.
TEST(Mp4Reader, ReadsEveryFrameAsTheTestReaderDoes) {
  ScratchDir dir;
  const std::string path = dir.file("gradient.mp4");
  Mp4Writer writer(path, 64, 48, 30);
  for (int i = 0; i < 12; ++i) writer.write_frame(test::moving_gradient(64, 48, i));
  writer.finish();

  const test::VideoFacts expected = test::read_video(path);
  ASSERT_EQ(expected.frames.size(), 12u);
  Mp4Reader reader(path);
  Image frame;
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(reader.read_frame(frame)) << "frame " << i;
    EXPECT_EQ(frame.width, 64);
    EXPECT_EQ(frame.height, 48);
    EXPECT_EQ(frame.rgb, expected.frames[i].rgb) << "frame " << i;
    // And close to what was encoded (the writer's tests measure the encoding loss).
    EXPECT_LT(compare_images(frame, test::moving_gradient(64, 48, i)).mean_abs_diff, 2.0) << i;
  }
  EXPECT_FALSE(reader.read_frame(frame));
  EXPECT_FALSE(reader.read_frame(frame));
  EXPECT_EQ(reader.frames_read(), 12);
}

TEST(Mp4Reader, MissingFileIsAnInputErrorNamingIt) {
  ScratchDir dir;
  const std::string path = dir.file("missing.mp4");
  EXPECT_EQ(error_of([&] { Mp4Reader reader(path); }),
            path + ": cannot open video: No such file or directory");
}

TEST(Mp4Reader, NotAVideoIsAnInputErrorNamingIt) {
  ScratchDir dir;
  const std::string path = dir.file("text.mp4");
  std::ofstream(path) << "not a video at all\n";
  const std::string error = error_of([&] { Mp4Reader reader(path); });
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

}  // namespace
}  // namespace tissu
