#include "video/frame_encoder_pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "video/png_io.h"
#include "video_test_support.h"

namespace tissu {
namespace {

using test::ScratchDir;

constexpr int kWidth = 320, kHeight = 240;

TEST(FrameEncoderPipeline, GivesTheSameBytesAsTheWriterAlone) {
  ScratchDir dir;
  {
    Mp4Writer direct(dir.file("direct.mp4"), kWidth, kHeight, 30);
    for (int i = 0; i < 30; ++i) direct.write_frame(test::moving_gradient(kWidth, kHeight, i));
    direct.finish();
  }
  for (const char* name : {"piped-1.mp4", "piped-2.mp4"}) {
    FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file(name), kWidth, kHeight, 30));
    for (int i = 0; i < 30; ++i) {
      Image frame = pipeline.take_frame_buffer(kWidth, kHeight);  // reused once frames are done
      const Image gradient = test::moving_gradient(kWidth, kHeight, i);
      std::copy(gradient.rgb.begin(), gradient.rgb.end(), frame.rgb.begin());
      pipeline.push(std::move(frame));
    }
    pipeline.finish();
    EXPECT_EQ(pipeline.frames_done(), 30);
  }
  const std::vector<char> direct = test::file_bytes(dir.file("direct.mp4"));
  EXPECT_GT(direct.size(), 1000u);
  EXPECT_TRUE(test::file_bytes(dir.file("piped-1.mp4")) == direct);
  EXPECT_TRUE(test::file_bytes(dir.file("piped-2.mp4")) == direct);
}

TEST(FrameEncoderPipeline, WritesPngsOfTheChosenFrames) {
  ScratchDir dir;
  FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file("run.mp4"), kWidth, kHeight, 30));
  for (int i = 0; i < 6; ++i) {
    std::vector<std::string> pngs;
    if (i % 3 == 0) pngs.push_back(dir.file("frame" + std::to_string(i) + ".png"));
    pipeline.push(test::moving_gradient(kWidth, kHeight, i), pngs);
  }
  pipeline.finish();
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"frame0.png", "frame3.png", "run.mp4"}));
  EXPECT_TRUE(read_png(dir.file("frame3.png")).rgb == test::moving_gradient(kWidth, kHeight, 3).rgb);
  EXPECT_EQ(test::read_video(dir.file("run.mp4")).frames.size(), 6u);
}

TEST(FrameEncoderPipeline, PngsOnlyWithoutVideo) {
  ScratchDir dir;
  FrameEncoderPipeline pipeline(nullptr);
  pipeline.push(test::moving_gradient(16, 8, 0), {dir.file("only.png")});
  pipeline.finish();
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"only.png"});
}

// A frame of a PNG sequence that is also a still goes to both files.
TEST(FrameEncoderPipeline, OneFrameToSeveralPngs) {
  ScratchDir dir;
  FrameEncoderPipeline pipeline(nullptr);
  pipeline.push(test::moving_gradient(16, 8, 0), {dir.file("a.png"), dir.file("b.png")});
  pipeline.finish();
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.png", "b.png"}));
  EXPECT_TRUE(read_png(dir.file("b.png")).rgb == test::moving_gradient(16, 8, 0).rgb);
}

// Encoding takes far longer than pushing, so without back-pressure the producer would run
// ahead; with it at most `capacity` frames wait plus the one being encoded.
TEST(FrameEncoderPipeline, QueueIsBounded) {
  ScratchDir dir;
  const std::size_t capacity = 2;
  FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file("run.mp4"), kWidth, kHeight, 30),
                                capacity);
  const Image frame = test::noise_image(kWidth, kHeight, 5);
  for (long long pushed = 1; pushed <= 20; ++pushed) {
    pipeline.push(frame);
    EXPECT_LE(pushed - pipeline.frames_done(), static_cast<long long>(capacity) + 1)
        << "after push " << pushed;
  }
  pipeline.finish();
  EXPECT_EQ(pipeline.frames_done(), 20);
}

TEST(FrameEncoderPipeline, WorkerErrorIsRethrownAndRemovesTheVideo) {
  ScratchDir dir;
  const std::string bad_png = dir.file("missing/frame.png");
  FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file("run.mp4"), kWidth, kHeight, 30));
  pipeline.push(test::moving_gradient(kWidth, kHeight, 0), {bad_png});
  std::string message;
  try {
    for (int i = 1; i < 1000; ++i) pipeline.push(test::moving_gradient(kWidth, kHeight, i));
    pipeline.finish();
  } catch (const OutputError& e) {
    message = e.what();
  }
  EXPECT_EQ(message, bad_png + ": cannot create PNG: No such file or directory");
  EXPECT_LT(pipeline.frames_done(), 4);          // stopped at the failure, not after 1000 frames
  EXPECT_THROW(pipeline.finish(), OutputError);  // finish() reports it as well
  EXPECT_TRUE(dir.entries().empty());
}

TEST(FrameEncoderPipeline, DestructionWithoutFinishLeavesNoFile) {
  ScratchDir dir;
  {
    FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file("run.mp4"), kWidth, kHeight, 30));
    for (int i = 0; i < 5; ++i) pipeline.push(test::moving_gradient(kWidth, kHeight, i));
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(FrameEncoderPipeline, RejectsFramesOfTheWrongSize) {
  ScratchDir dir;
  FrameEncoderPipeline pipeline(std::make_unique<Mp4Writer>(dir.file("run.mp4"), kWidth, kHeight, 30));
  EXPECT_THROW(pipeline.push(Image(kWidth, kHeight + 2)), std::invalid_argument);
  pipeline.abort();
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace tissu
