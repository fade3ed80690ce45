// A small rasterizer for log-log plots: anti-aliased lines, markers, text, decade axes,
// legend. Draws into a tissu::Image (write it with write_png).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "text/text_bitmap.h"
#include "video/image.h"

namespace tissu {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

enum class Marker { Circle, Square, TriangleUp, Diamond, Cross, TriangleDown };
enum class Align { Start, Center, End };

// Maps `value` on a log10 scale: lo -> pixel_lo, hi -> pixel_hi (either may be larger).
double log_scale(double value, double lo, double hi, double pixel_lo, double pixel_hi);

// Whole decades [10^a, 10^b] containing every positive value (at least one decade wide).
void decade_range(const std::vector<double>& values, double& lo, double& hi);

class Canvas {
 public:
  Canvas(int width, int height, Rgb background);
  const Image& image() const { return image_; }
  int width() const { return image_.width; }
  int height() const { return image_.height; }

  // Blends `color` over pixel (x, y) with opacity `alpha` in [0, 1]; outside = ignored.
  void blend(int x, int y, Rgb color, double alpha);
  void fill_rect(double x0, double y0, double x1, double y1, Rgb color);
  void rect_outline(double x0, double y0, double x1, double y1, Rgb color, double width);
  // A segment `width` pixels wide with round ends; dash > 0 draws dash-length on/off.
  void line(double x0, double y0, double x1, double y1, Rgb color, double width,
            double dash = 0.0);
  void marker(Marker shape, double x, double y, double size, Rgb color);
  // Text anchored at (x, y): horizontal/vertical alignment of its box; `vertical` turns it
  // 90 degrees counter-clockwise (reading upwards).
  void text(const BitmapFont& font, const std::string& s, double x, double y, double pixel_height,
            Rgb color, Align h = Align::Start, Align v = Align::Start, bool vertical = false);

 private:
  // Coverage-weighted fill of a shape given by its signed distance (px, negative inside).
  template <class Sdf>
  void fill_sdf(double x0, double y0, double x1, double y1, Rgb color, Sdf sdf);
  Image image_;
};

struct Series {
  std::string name;
  std::vector<double> x, y;  // positive data values, joined in the order given
  Rgb color;
  Marker marker = Marker::Circle;
  bool dashed = false;
};

// A horizontal reference line across the plot (e.g. the reference solution's own error).
struct HorizontalLine {
  std::string name;
  double y = 0.0;
  Rgb color{120, 120, 120};
};

struct LogLogPlot {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<HorizontalLine> lines;
  int width = 960, height = 640;  // px
};

// Where the data go: the plot rectangle in pixels and the decade ranges of the axes.
struct PlotFrame {
  double left = 0, right = 0, top = 0, bottom = 0;  // px
  double x_lo = 1, x_hi = 10, y_lo = 1, y_hi = 10;  // data
  double px(double x) const { return log_scale(x, x_lo, x_hi, left, right); }
  double py(double y) const { return log_scale(y, y_lo, y_hi, bottom, top); }
};
PlotFrame plot_frame(const LogLogPlot& plot);

// Draws the plot: white background, decade grid and labels, one polyline with markers per
// series, legend in the top right corner. Non-positive values are left out.
Image render_plot(const LogLogPlot& plot, const BitmapFont& font);

// A palette of distinct colours and markers for series number `i`.
Rgb series_color(int i);
Marker series_marker(int i);

}  // namespace tissu
