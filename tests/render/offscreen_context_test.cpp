#include "render/gl/offscreen_context.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "render/gl/gl.h"
#include "render/render_error.h"
#include "test_scenes.h"

namespace tissu {
namespace {

using test::pixel;

// Clears the top half red and the bottom half blue (GL's y runs upwards).
void clear_halves(OffscreenContext& context) {
  context.bind_draw_target();
  glEnable(GL_SCISSOR_TEST);
  const int half = context.height() / 2;
  glScissor(0, half, context.width(), context.height() - half);
  glClearColor(1, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glScissor(0, 0, context.width(), half);
  glClearColor(0, 0, 1, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
}

TEST(render_context, GivesCoreProfile33OrHigher) {
  OffscreenContext context(64, 32, 1);
  EXPECT_TRUE(context.core_profile());
  EXPECT_GE(context.gl_major() * 10 + context.gl_minor(), 33) << context.gl_version();
  EXPECT_FALSE(context.gl_renderer().empty());
}

TEST(render_context, ReadsRowsFromTopToBottom) {
  OffscreenContext context(32, 16, 1);
  clear_halves(context);
  std::vector<uint8_t> rgb;
  context.read_rgb(rgb);
  ASSERT_EQ(rgb.size(), 32u * 16u * 3u);
  EXPECT_EQ(pixel(rgb, 32, 5, 0).r, 255);
  EXPECT_EQ(pixel(rgb, 32, 5, 0).b, 0);
  EXPECT_EQ(pixel(rgb, 32, 5, 15).r, 0);
  EXPECT_EQ(pixel(rgb, 32, 5, 15).b, 255);
}

TEST(render_context, MultisampledFramebufferIsResolved) {
  OffscreenContext context(32, 16, 4);
  EXPECT_EQ(context.samples(), 4);
  clear_halves(context);
  std::vector<uint8_t> rgb;
  context.read_rgb(rgb);
  EXPECT_EQ(pixel(rgb, 32, 31, 0).r, 255);
  EXPECT_EQ(pixel(rgb, 32, 31, 15).b, 255);
}

TEST(render_context, TwoSamplesGiveAtLeastTwo) {
  OffscreenContext context(16, 16, 2);
  EXPECT_GE(context.samples(), 2);
}

TEST(render_context, RejectsUnsupportedSampleCount) {
  EXPECT_THROW(OffscreenContext(16, 16, 3), RenderError);
}

TEST(render_context, FailureToCreateTellsWhy) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // Forcing Mesa down to OpenGL 3.0 leaves no 3.3 core profile to give.
  EXPECT_EXIT(
      {
        setenv("MESA_GL_VERSION_OVERRIDE", "3.0", 1);
        try {
          OffscreenContext context(16, 16, 1);
        } catch (const RenderError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(3);
        }
        std::exit(0);
      },
      testing::ExitedWithCode(3),
      "offscreen context: OSMesaCreateContextAttribs failed: this Mesa offers no OpenGL 3.3 "
      "core profile; its default context is OpenGL 3.0.*environment: "
      "MESA_GL_VERSION_OVERRIDE=3.0");
}

}  // namespace
}  // namespace tissu
