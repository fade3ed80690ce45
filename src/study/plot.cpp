#include "study/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tissu {

namespace {

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kBlack{0, 0, 0};
constexpr Rgb kAxis{40, 40, 40};
constexpr Rgb kMajorGrid{215, 215, 215};
constexpr Rgb kMinorGrid{238, 238, 238};

double clamp01(double a) { return std::min(1.0, std::max(0.0, a)); }

// Distance from p to the segment a-b, px.
double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  const double cx = ax + t * dx - px, cy = ay + t * dy - py;
  return std::sqrt(cx * cx + cy * cy);
}

// Decade label: plain decimals from 0.001 to 10000, powers of ten beyond.
std::string decade_label(int exponent) {
  char buf[32];
  if (exponent >= -3 && exponent <= 4) {
    std::snprintf(buf, sizeof(buf), "%.*f", exponent < 0 ? -exponent : 0, std::pow(10.0, exponent));
  } else {
    std::snprintf(buf, sizeof(buf), "1e%d", exponent);
  }
  return buf;
}

}  // namespace

double log_scale(double value, double lo, double hi, double pixel_lo, double pixel_hi) {
  const double a = (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  return pixel_lo + a * (pixel_hi - pixel_lo);
}

void decade_range(const std::vector<double>& values, double& lo, double& hi) {
  double vmin = INFINITY, vmax = 0.0;
  for (double v : values) {
    if (v > 0.0 && std::isfinite(v)) {
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
    }
  }
  if (!(vmax > 0.0)) {
    lo = 1.0;
    hi = 10.0;
    return;
  }
  const int a = static_cast<int>(std::floor(std::log10(vmin) + 1e-9));
  int b = static_cast<int>(std::ceil(std::log10(vmax) - 1e-9));
  if (b <= a) b = a + 1;
  lo = std::pow(10.0, a);
  hi = std::pow(10.0, b);
}

Canvas::Canvas(int width, int height, Rgb background) : image_(width, height) {
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image_.pixel(x, y);
      p[0] = background.r;
      p[1] = background.g;
      p[2] = background.b;
    }
  }
}

void Canvas::blend(int x, int y, Rgb c, double alpha) {
  if (x < 0 || y < 0 || x >= image_.width || y >= image_.height || alpha <= 0.0) return;
  alpha = clamp01(alpha);
  std::uint8_t* p = image_.pixel(x, y);
  const std::uint8_t src[3] = {c.r, c.g, c.b};
  for (int k = 0; k < 3; ++k) {
    p[k] = static_cast<std::uint8_t>(std::lround(p[k] + alpha * (src[k] - p[k])));
  }
}

template <class Sdf>
void Canvas::fill_sdf(double x0, double y0, double x1, double y1, Rgb color, Sdf sdf) {
  const int ix0 = std::max(0, static_cast<int>(std::floor(std::min(x0, x1))) - 1);
  const int iy0 = std::max(0, static_cast<int>(std::floor(std::min(y0, y1))) - 1);
  const int ix1 = std::min(image_.width - 1, static_cast<int>(std::ceil(std::max(x0, x1))) + 1);
  const int iy1 = std::min(image_.height - 1, static_cast<int>(std::ceil(std::max(y0, y1))) + 1);
  for (int y = iy0; y <= iy1; ++y) {
    for (int x = ix0; x <= ix1; ++x) {
      const double coverage = clamp01(0.5 - sdf(x + 0.5, y + 0.5));
      if (coverage > 0.0) blend(x, y, color, coverage);
    }
  }
}

void Canvas::fill_rect(double x0, double y0, double x1, double y1, Rgb color) {
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const double hx = 0.5 * std::fabs(x1 - x0), hy = 0.5 * std::fabs(y1 - y0);
  fill_sdf(x0, y0, x1, y1, color, [&](double px, double py) {
    return std::max(std::fabs(px - cx) - hx, std::fabs(py - cy) - hy);
  });
}

void Canvas::rect_outline(double x0, double y0, double x1, double y1, Rgb color, double width) {
  line(x0, y0, x1, y0, color, width);
  line(x1, y0, x1, y1, color, width);
  line(x1, y1, x0, y1, color, width);
  line(x0, y1, x0, y0, color, width);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb color, double width,
                  double dash) {
  const double half = 0.5 * width;
  auto solid = [&](double ax, double ay, double bx, double by) {
    fill_sdf(std::min(ax, bx) - half, std::min(ay, by) - half, std::max(ax, bx) + half,
             std::max(ay, by) + half, color, [&](double px, double py) {
               return segment_distance(px, py, ax, ay, bx, by) - half;
             });
  };
  const double length = std::hypot(x1 - x0, y1 - y0);
  if (dash <= 0.0 || length <= dash) {
    solid(x0, y0, x1, y1);
    return;
  }
  // Dashes: `dash` px on, `dash` px off, from the start.
  for (double s = 0.0; s < length; s += 2.0 * dash) {
    const double e = std::min(length, s + dash);
    solid(x0 + (x1 - x0) * s / length, y0 + (y1 - y0) * s / length,
          x0 + (x1 - x0) * e / length, y0 + (y1 - y0) * e / length);
  }
}

void Canvas::marker(Marker shape, double x, double y, double size, Rgb color) {
  const double r = 0.5 * size;
  switch (shape) {
    case Marker::Circle:
      fill_sdf(x - r, y - r, x + r, y + r, color,
               [&](double px, double py) { return std::hypot(px - x, py - y) - r; });
      break;
    case Marker::Square: {
      const double h = 0.85 * r;
      fill_sdf(x - h, y - h, x + h, y + h, color, [&](double px, double py) {
        return std::max(std::fabs(px - x), std::fabs(py - y)) - h;
      });
      break;
    }
    case Marker::Diamond:
      fill_sdf(x - r, y - r, x + r, y + r, color, [&](double px, double py) {
        return (std::fabs(px - x) + std::fabs(py - y) - r) / std::sqrt(2.0);
      });
      break;
    case Marker::TriangleUp:
    case Marker::TriangleDown: {
      // Intersection of three half-planes; edge normals of an equilateral triangle
      // (screen y grows downwards: mirror y for the downward one).
      const double k = std::sqrt(3.0) / 2.0;
      const double flip = shape == Marker::TriangleUp ? 1.0 : -1.0;
      fill_sdf(x - r, y - r, x + r, y + r, color, [&](double px, double py) {
        const double dx = px - x, dy = flip * (py - y) - 0.15 * r;
        const double bottom = dy - 0.5 * r;
        const double left = -k * dx - 0.5 * dy - 0.5 * r;
        const double right = k * dx - 0.5 * dy - 0.5 * r;
        return std::max(bottom, std::max(left, right));
      });
      break;
    }
    case Marker::Cross:
      line(x - 0.8 * r, y - 0.8 * r, x + 0.8 * r, y + 0.8 * r, color, 0.35 * size);
      line(x - 0.8 * r, y + 0.8 * r, x + 0.8 * r, y - 0.8 * r, color, 0.35 * size);
      break;
  }
}

void Canvas::text(const BitmapFont& font, const std::string& s, double x, double y,
                  double pixel_height, Rgb color, Align h, Align v, bool vertical) {
  const TextBitmap bm = font.render(s, pixel_height);
  const int box_w = vertical ? bm.height : bm.width;
  const int box_h = vertical ? bm.width : bm.height;
  auto offset = [](Align a, int size) {
    return a == Align::Start ? 0.0 : (a == Align::Center ? -0.5 * size : -double(size));
  };
  const int x0 = static_cast<int>(std::lround(x + offset(h, box_w)));
  const int y0 = static_cast<int>(std::lround(y + offset(v, box_h)));
  for (int by = 0; by < bm.height; ++by) {
    for (int bx = 0; bx < bm.width; ++bx) {
      const std::uint8_t c = bm.coverage[static_cast<size_t>(by) * bm.width + bx];
      if (c == 0) continue;
      if (vertical) {
        blend(x0 + by, y0 + (bm.width - 1 - bx), color, c / 255.0);
      } else {
        blend(x0 + bx, y0 + by, color, c / 255.0);
      }
    }
  }
}

Rgb series_color(int i) {
  static const Rgb palette[] = {{214, 39, 40},  {31, 119, 180}, {44, 160, 44},
                                {148, 103, 189}, {255, 127, 14}, {140, 86, 75},
                                {227, 119, 194}, {23, 190, 207}};
  return palette[i % 8];
}

Marker series_marker(int i) {
  static const Marker markers[] = {Marker::Circle,  Marker::Square, Marker::TriangleUp,
                                   Marker::Diamond, Marker::Cross,  Marker::TriangleDown};
  return markers[i % 6];
}

PlotFrame plot_frame(const LogLogPlot& plot) {
  PlotFrame f;
  f.left = 100;
  f.right = plot.width - 230;
  f.top = 56;
  f.bottom = plot.height - 78;
  std::vector<double> xs, ys;
  for (const Series& s : plot.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
  }
  for (const HorizontalLine& l : plot.lines) ys.push_back(l.y);
  decade_range(xs, f.x_lo, f.x_hi);
  decade_range(ys, f.y_lo, f.y_hi);
  return f;
}

Image render_plot(const LogLogPlot& plot, const BitmapFont& font) {
  Canvas c(plot.width, plot.height, kWhite);
  const PlotFrame f = plot_frame(plot);
  const double tick_font = 15, label_font = 17, title_font = 20;

  // Grid: decades (major) and 2..9 times a decade (minor), x then y.
  const int x_a = static_cast<int>(std::lround(std::log10(f.x_lo)));
  const int x_b = static_cast<int>(std::lround(std::log10(f.x_hi)));
  const int y_a = static_cast<int>(std::lround(std::log10(f.y_lo)));
  const int y_b = static_cast<int>(std::lround(std::log10(f.y_hi)));
  for (int e = x_a; e <= x_b; ++e) {
    for (int m = 1; m <= 9 && (e < x_b || m == 1); ++m) {
      const double px = f.px(m * std::pow(10.0, e));
      c.line(px, f.top, px, f.bottom, m == 1 ? kMajorGrid : kMinorGrid, 1.0);
      c.line(px, f.bottom, px, f.bottom + (m == 1 ? 7 : 4), kAxis, 1.0);
    }
    c.text(font, decade_label(e), f.px(std::pow(10.0, e)), f.bottom + 10, tick_font, kBlack,
           Align::Center, Align::Start);
  }
  for (int e = y_a; e <= y_b; ++e) {
    for (int m = 1; m <= 9 && (e < y_b || m == 1); ++m) {
      const double py = f.py(m * std::pow(10.0, e));
      c.line(f.left, py, f.right, py, m == 1 ? kMajorGrid : kMinorGrid, 1.0);
      c.line(f.left - (m == 1 ? 7 : 4), py, f.left, py, kAxis, 1.0);
    }
    c.text(font, decade_label(e), f.left - 10, f.py(std::pow(10.0, e)), tick_font, kBlack,
           Align::End, Align::Center);
  }
  c.rect_outline(f.left, f.top, f.right, f.bottom, kAxis, 1.2);

  // Labels and title.
  c.text(font, plot.title, 0.5 * (f.left + f.right), 14, title_font, kBlack, Align::Center,
         Align::Start);
  c.text(font, plot.x_label, 0.5 * (f.left + f.right), plot.height - 30, label_font, kBlack,
         Align::Center, Align::Start);
  c.text(font, plot.y_label, 18, 0.5 * (f.top + f.bottom), label_font, kBlack, Align::Start,
         Align::Center, /*vertical=*/true);

  // Reference lines, then the series on top.
  for (const HorizontalLine& l : plot.lines) {
    c.line(f.left, f.py(l.y), f.right, f.py(l.y), l.color, 1.5, 6.0);
  }
  for (const Series& s : plot.series) {
    double last_x = 0, last_y = 0;
    bool have_last = false;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!(s.x[i] > 0.0) || !(s.y[i] > 0.0)) continue;
      const double px = f.px(s.x[i]), py = f.py(s.y[i]);
      if (have_last) c.line(last_x, last_y, px, py, s.color, 2.0, s.dashed ? 6.0 : 0.0);
      last_x = px;
      last_y = py;
      have_last = true;
    }
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!(s.x[i] > 0.0) || !(s.y[i] > 0.0)) continue;
      c.marker(s.marker, f.px(s.x[i]), f.py(s.y[i]), 10.0, s.color);
    }
  }

  // Legend, right of the plot.
  const double lx = f.right + 18;
  double ly = f.top + 8;
  for (const Series& s : plot.series) {
    c.line(lx, ly + 9, lx + 34, ly + 9, s.color, 2.0, s.dashed ? 6.0 : 0.0);
    c.marker(s.marker, lx + 17, ly + 9, 10.0, s.color);
    c.text(font, s.name, lx + 42, ly + 9, tick_font, kBlack, Align::Start, Align::Center);
    ly += 26;
  }
  for (const HorizontalLine& l : plot.lines) {
    c.line(lx, ly + 9, lx + 34, ly + 9, l.color, 1.5, 6.0);
    c.text(font, l.name, lx + 42, ly + 9, tick_font, kBlack, Align::Start, Align::Center);
    ly += 26;
  }
  return c.image();
}

}  // namespace tissu
