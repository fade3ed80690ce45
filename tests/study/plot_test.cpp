// The plot rasterizer: log-scale mapping, decade ranges, and a rendered PNG with lines and
// markers where the data put them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "study/plot.h"
#include "video/png_io.h"

namespace tissu {
namespace {

TEST(LogScale, MapsDecadesLinearly) {
  EXPECT_DOUBLE_EQ(log_scale(1.0, 1.0, 100.0, 0.0, 200.0), 0.0);
  EXPECT_DOUBLE_EQ(log_scale(10.0, 1.0, 100.0, 0.0, 200.0), 100.0);
  EXPECT_DOUBLE_EQ(log_scale(100.0, 1.0, 100.0, 0.0, 200.0), 200.0);
  EXPECT_NEAR(log_scale(std::sqrt(10.0), 1.0, 100.0, 0.0, 200.0), 50.0, 1e-12);
  // Screen y grows downwards: a reversed pixel range.
  EXPECT_DOUBLE_EQ(log_scale(1e-3, 1e-3, 1e-1, 500.0, 100.0), 500.0);
  EXPECT_DOUBLE_EQ(log_scale(1e-2, 1e-3, 1e-1, 500.0, 100.0), 300.0);
}

TEST(DecadeRange, CoversTheDataWithWholeDecades) {
  double lo, hi;
  decade_range({0.03, 7.0, 250.0}, lo, hi);
  EXPECT_DOUBLE_EQ(lo, 0.01);
  EXPECT_DOUBLE_EQ(hi, 1000.0);
  decade_range({10.0, 100.0}, lo, hi);  // exact decades stay
  EXPECT_DOUBLE_EQ(lo, 10.0);
  EXPECT_DOUBLE_EQ(hi, 100.0);
  decade_range({5.0}, lo, hi);  // one value: one decade
  EXPECT_DOUBLE_EQ(lo, 1.0);
  EXPECT_DOUBLE_EQ(hi, 10.0);
  decade_range({-1.0, 0.0}, lo, hi);  // nothing positive
  EXPECT_DOUBLE_EQ(lo, 1.0);
  EXPECT_DOUBLE_EQ(hi, 10.0);
}

bool is_white(const Image& im, int x, int y) {
  const std::uint8_t* p = im.pixel(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

// Close to `c` (the series colour, fully covered).
bool is_colour(const Image& im, int x, int y, Rgb c) {
  const std::uint8_t* p = im.pixel(x, y);
  return std::abs(p[0] - c.r) < 40 && std::abs(p[1] - c.g) < 40 && std::abs(p[2] - c.b) < 40;
}

TEST(RenderPlot, PngWithLineAndMarkersWhereTheDataAre) {
  LogLogPlot plot;
  plot.title = "test";
  plot.x_label = "x";
  plot.y_label = "y";
  plot.width = 800;
  plot.height = 500;
  Series s;
  s.name = "series";
  s.color = Rgb{200, 0, 0};
  s.x = {0.2, 20.0};
  s.y = {3.0, 300.0};
  plot.series.push_back(s);
  const BitmapFont font(default_font_file());
  const Image image = render_plot(plot, font);

  // Written and read back as a PNG of the requested size.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("tissu_plot_" + std::to_string(::getpid()) + ".png")).string();
  write_png(path, image);
  const Image back = read_png(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.width, 800);
  ASSERT_EQ(back.height, 500);

  const PlotFrame f = plot_frame(plot);
  EXPECT_DOUBLE_EQ(f.x_lo, 0.1);
  EXPECT_DOUBLE_EQ(f.x_hi, 100.0);
  EXPECT_DOUBLE_EQ(f.y_lo, 1.0);
  EXPECT_DOUBLE_EQ(f.y_hi, 1000.0);
  // Markers at both points, and the line through the midpoint (in log space: 2, 30).
  for (auto [x, y] : {std::pair{0.2, 3.0}, std::pair{20.0, 300.0}, std::pair{2.0, 30.0}}) {
    const int px = static_cast<int>(f.px(x)), py = static_cast<int>(f.py(y));
    EXPECT_TRUE(is_colour(back, px, py, s.color)) << x << ", " << y;
  }
  // Far from the line, inside the plot area, away from grid lines: background.
  const int px = static_cast<int>(f.px(30.0)) + 3, py = static_cast<int>(f.py(1.5)) + 3;
  EXPECT_TRUE(is_white(back, px, py));
  // Something (tick labels, title) is drawn outside the plot rectangle, in black.
  int dark = 0;
  for (int y = 0; y < static_cast<int>(f.top); ++y) {
    for (int x = 0; x < back.width; ++x) dark += back.pixel(x, y)[0] < 100;
  }
  EXPECT_GT(dark, 20) << "title text";
}

TEST(Canvas, LineCoversItsPixelsAndNothingFar) {
  Canvas c(50, 50, Rgb{255, 255, 255});
  c.line(5, 25, 45, 25, Rgb{0, 0, 0}, 3.0);
  EXPECT_EQ(c.image().pixel(25, 25)[0], 0);
  EXPECT_EQ(c.image().pixel(25, 30)[0], 255);
  EXPECT_EQ(c.image().pixel(2, 25)[0], 255);  // beyond the round cap
}

TEST(Canvas, TextDrawsInk) {
  Canvas c(200, 60, Rgb{255, 255, 255});
  const BitmapFont font(default_font_file());
  c.text(font, "10^3 mm", 10, 10, 20, Rgb{0, 0, 0});
  int ink = 0;
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 200; ++x) ink += c.image().pixel(x, y)[0] < 128;
  }
  EXPECT_GT(ink, 50);
}

}  // namespace
}  // namespace tissu
