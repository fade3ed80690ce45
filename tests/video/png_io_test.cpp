#include "video/png_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "core/error.h"
#include "video_test_support.h"

// stb, an independent PNG codec, checks the files from the other side.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

namespace tissu {
namespace {

using test::ScratchDir;

template <typename Error, typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(Png, RoundTripIsExact) {
  ScratchDir dir;
  const Image original = test::noise_image(321, 123, 7);  // odd sizes, every byte value
  write_png(dir.file("noise.png"), original);
  const Image back = read_png(dir.file("noise.png"));
  EXPECT_EQ(back.width, 321);
  EXPECT_EQ(back.height, 123);
  EXPECT_TRUE(back.rgb == original.rgb);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"noise.png"});  // no temporary file left
}

// A frame-sized image of noise does not compress: igzip falls back to stored blocks, which
// must fit the room the writer gives them. Flat and smooth images (the usual frames)
// compress; each size, two decoders and the round trip agree.
TEST(Png, IncompressibleAndFlatFramesRoundTripThroughTwoDecoders) {
  ScratchDir dir;
  Image flat(1280, 720);
  for (int y = 0; y < 720; ++y) {
    for (int x = 0; x < 1280; ++x) {
      std::uint8_t* p = flat.pixel(x, y);
      p[0] = 120, p[1] = static_cast<std::uint8_t>(y / 3), p[2] = x < 640 ? 30 : 200;
    }
  }
  for (const Image& image : {test::noise_image(1280, 720, 5), flat, test::noise_image(1, 1, 2)}) {
    const std::string file = dir.file("frame.png");
    write_png(file, image);
    EXPECT_TRUE(read_png(file).rgb == image.rgb) << image.width << "x" << image.height;
    int width = 0, height = 0, channels = 0;
    std::uint8_t* pixels = stbi_load(file.c_str(), &width, &height, &channels, 3);
    ASSERT_NE(pixels, nullptr);
    EXPECT_TRUE(std::vector<std::uint8_t>(pixels, pixels + image.rgb.size()) == image.rgb);
    stbi_image_free(pixels);
  }
  // Noise stays about its own size; the flat frame is a small fraction of it.
  EXPECT_LT(encode_png(flat.rgb.data(), 1280, 720).size(), flat.rgb.size() / 50);
}

TEST(Png, EmptySizeIsAnInvalidArgumentNamingTheFile) {
  ScratchDir dir;
  const std::string path = dir.file("empty.png");
  const std::uint8_t pixel[3] = {0, 0, 0};
  EXPECT_EQ(error_of<std::invalid_argument>([&] { write_png(path, pixel, 0, 240); }),
            path + ": PNG size must be positive, got 0x240");
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Png, AnotherDecoderReadsTheSamePixelsTopRowFirst) {
  ScratchDir dir;
  Image image = test::noise_image(5, 3, 11);
  image.pixel(0, 0)[0] = 255, image.pixel(0, 0)[1] = 0, image.pixel(0, 0)[2] = 0;  // top-left red
  write_png(dir.file("small.png"), image);
  int width = 0, height = 0, channels = 0;
  std::uint8_t* pixels = stbi_load(dir.file("small.png").c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr);
  EXPECT_EQ(width, 5);
  EXPECT_EQ(height, 3);
  EXPECT_TRUE(std::vector<std::uint8_t>(pixels, pixels + 45) == image.rgb);
  stbi_image_free(pixels);
}

TEST(Png, ReadsGrayAndAlphaAsRgb) {
  ScratchDir dir;
  const std::uint8_t gray[4] = {0, 85, 170, 255};
  ASSERT_TRUE(stbi_write_png(dir.file("gray.png").c_str(), 2, 2, 1, gray, 2));
  const Image g = read_png(dir.file("gray.png"));
  ASSERT_EQ(g.rgb.size(), 12u);
  EXPECT_EQ((std::vector<int>(g.rgb.begin(), g.rgb.end())),
            (std::vector<int>{0, 0, 0, 85, 85, 85, 170, 170, 170, 255, 255, 255}));

  const std::uint8_t rgba[8] = {10, 20, 30, 0, 40, 50, 60, 255};
  ASSERT_TRUE(stbi_write_png(dir.file("rgba.png").c_str(), 2, 1, 4, rgba, 8));
  const Image c = read_png(dir.file("rgba.png"));
  EXPECT_EQ((std::vector<int>(c.rgb.begin(), c.rgb.end())), (std::vector<int>{10, 20, 30, 40, 50, 60}));
}

TEST(Png, WriteToMissingDirectoryIsAnOutputError) {
  ScratchDir dir;
  const std::string path = dir.file("missing/frame.png");
  const std::string message = error_of<OutputError>([&] { write_png(path, Image(4, 4)); });
  EXPECT_EQ(message, path + ": cannot create PNG: No such file or directory");
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Png, FullDeviceIsAnOutputErrorAndLeavesNoFile) {
  // /dev/full fails every write with ENOSPC. The temporary file is made in the target's
  // directory, so aim there through a symlink named like the temporary file.
  ScratchDir dir;
  const std::string path = dir.file("frame.png");
  ASSERT_EQ(symlink("/dev/full", dir.file(".frame.png.partial").c_str()), 0);
  const std::string message = error_of<OutputError>([&] { write_png(path, test::noise_image(64, 64, 1)); });
  EXPECT_EQ(message, path + ": cannot write PNG: No space left on device");
  EXPECT_TRUE(dir.entries().empty());  // the symlink (the temporary name) is removed too
}

TEST(Png, ReadingMissingOrBrokenFilesIsAnInputError) {
  ScratchDir dir;
  const std::string missing = dir.file("missing.png");
  EXPECT_EQ(error_of<InputError>([&] { read_png(missing); }),
            missing + ": cannot open PNG: No such file or directory");

  const std::string text = dir.file("text.png");
  std::ofstream(text) << "not a png at all";
  EXPECT_EQ(error_of<InputError>([&] { read_png(text); }), text + ": not a readable PNG: Not a PNG file");

  // A valid PNG cut in half.
  write_png(dir.file("whole.png"), test::noise_image(64, 64, 3));
  std::vector<char> bytes = test::file_bytes(dir.file("whole.png"));
  const std::string cut = dir.file("cut.png");
  std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
  const std::string message = error_of<InputError>([&] { read_png(cut); });
  EXPECT_EQ(message.rfind(cut + ": not a readable PNG: ", 0), 0u) << message;
}

}  // namespace
}  // namespace tissu
