#include "render/draw/ground_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissu {

namespace {

// Keeps the part of a convex polygon where dot(n, p) + c >= 0 (Sutherland-Hodgman).
template <class P, class Side>
std::vector<P> clip(const std::vector<P>& polygon, Side side) {
  std::vector<P> out;
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const P& a = polygon[i];
    const P& b = polygon[(i + 1) % n];
    const double sa = side(a), sb = side(b);
    if (sa >= 0) out.push_back(a);
    if ((sa >= 0) != (sb >= 0)) {
      const double t = sa / (sa - sb);
      out.push_back(a + static_cast<float>(t) * (b - a));
    }
  }
  return out;
}

}  // namespace

std::optional<GroundRect> shadow_footprint(const std::vector<Vec3>& points, const Vec3& direction,
                                           double height, double margin) {
  if (points.empty()) return std::nullopt;
  const Vec3 d = direction.normalized();
  if (!(d.z() < -1e-6)) return std::nullopt;
  GroundRect r{glm::dvec2(1e300), glm::dvec2(-1e300)};
  for (const Vec3& c : points) {
    // Along the light to the plane (corners below the plane project back up: still a bound).
    const Vec3 p = c + d * ((height - c.z()) / d.z());
    r.min = glm::min(r.min, glm::dvec2(p.x(), p.y()));
    r.max = glm::max(r.max, glm::dvec2(p.x(), p.y()));
  }
  r.min -= glm::dvec2(margin);
  r.max += glm::dvec2(margin);
  return r;
}

SplitGround split_ground(const GroundRect& square, double height, const glm::dvec2& fade_centre,
                         double opaque_radius, int divisions) {
  const int n = std::max(divisions, 1);
  auto lines = [&](double lo, double hi) {
    std::vector<float> at;
    for (int i = 0; i <= n; ++i) at.push_back(static_cast<float>(i == n ? hi : lo + (hi - lo) * i / n));
    return at;
  };
  const std::vector<float> xs = lines(square.min.x, square.max.x);
  const std::vector<float> ys = lines(square.min.y, square.max.y);
  const glm::vec3 normal(0, 0, 1);
  const float z = static_cast<float>(height);
  std::vector<MeshVertex> grid;
  for (float y : ys) {
    for (float x : xs) grid.push_back({glm::vec3(x, y, z), normal, glm::vec2(0.0f)});
  }
  SplitGround split;
  split.fading.vertices = grid;
  split.opaque.vertices = grid;
  const uint32_t row = static_cast<uint32_t>(xs.size());
  for (uint32_t j = 0; j + 1 < ys.size(); ++j) {
    for (uint32_t i = 0; i + 1 < xs.size(); ++i) {
      const double x0 = xs[i], x1 = xs[i + 1], y0 = ys[j], y1 = ys[j + 1];
      const bool opaque = opaque_radius > 0.0 &&
                          rect_within_disc(GroundRect{{x0, y0}, {x1, y1}}, fade_centre, opaque_radius);
      IndexedMesh& part = opaque ? split.opaque : split.fading;
      const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      part.indices.insert(part.indices.end(), {a, b, d, a, d, c});
    }
  }
  return split;
}

std::optional<IndexedMesh> ground_ring(const GroundRect& square, double height,
                                       const glm::dvec2& fade_centre, double opaque_radius, int sides) {
  const int n = std::max(sides, 8);
  const glm::dvec2& c = fade_centre;
  if (!(opaque_radius > 0.0) || c.x - opaque_radius <= square.min.x ||
      c.x + opaque_radius >= square.max.x || c.y - opaque_radius <= square.min.y ||
      c.y + opaque_radius >= square.max.y) {
    return std::nullopt;
  }
  // Rays at n even angles and through the four corners, in angle order: consecutive rays
  // meet the square on one side, so each quad is convex.
  std::vector<double> angles;
  for (int k = 0; k < n; ++k) angles.push_back(2.0 * M_PI * k / n);
  const glm::dvec2 corners[4] = {square.min, glm::dvec2(square.max.x, square.min.y), square.max,
                                 glm::dvec2(square.min.x, square.max.y)};
  for (const glm::dvec2& corner : corners) {
    const double a = std::atan2(corner.y - c.y, corner.x - c.x);
    angles.push_back(a < 0.0 ? a + 2.0 * M_PI : a);
  }
  std::sort(angles.begin(), angles.end());
  // A corner's ray that is also an even one (the centre in the square's middle) once only.
  angles.erase(std::unique(angles.begin(), angles.end(),
                           [](double a, double b) { return b - a < 1e-12; }),
               angles.end());

  const glm::vec3 normal(0, 0, 1);
  const float z = static_cast<float>(height);
  auto vertex = [&](const glm::dvec2& p) {
    return MeshVertex{glm::vec3(static_cast<float>(p.x), static_cast<float>(p.y), z), normal, glm::vec2(0.0f)};
  };
  IndexedMesh ring;
  const uint32_t m = static_cast<uint32_t>(angles.size());
  for (uint32_t k = 0; k < m; ++k) {
    const glm::dvec2 d(std::cos(angles[k]), std::sin(angles[k]));
    // Where the ray leaves the square (exactly the corner for a corner's ray).
    double t = std::numeric_limits<double>::infinity();
    if (d.x != 0.0) t = std::min(t, ((d.x > 0.0 ? square.max.x : square.min.x) - c.x) / d.x);
    if (d.y != 0.0) t = std::min(t, ((d.y > 0.0 ? square.max.y : square.min.y) - c.y) / d.y);
    glm::dvec2 out = c + t * d;
    for (const glm::dvec2& corner : corners) {
      if (glm::length(out - corner) < 1e-9 * (square.max.x - square.min.x)) out = corner;
    }
    ring.vertices.push_back(vertex(c + opaque_radius * d));  // 2k: on the polygon
    ring.vertices.push_back(vertex(out));                    // 2k + 1: on the square
  }
  for (uint32_t k = 0; k < m; ++k) {
    const uint32_t p = 2 * k, q = p + 1, p_next = 2 * ((k + 1) % m), q_next = p_next + 1;
    ring.indices.insert(ring.indices.end(), {p, q, q_next, p, q_next, p_next});
  }
  return ring;
}

bool rect_within_disc(const GroundRect& rect, const glm::dvec2& centre, double radius) {
  // A rectangle is convex, and so is the disc: all four corners inside means all of it.
  for (const glm::dvec2& p : {rect.min, rect.max, glm::dvec2(rect.min.x, rect.max.y),
                              glm::dvec2(rect.max.x, rect.min.y)}) {
    const glm::dvec2 d = p - centre;
    if (d.x * d.x + d.y * d.y > radius * radius) return false;
  }
  return true;
}

std::vector<glm::vec2> outside_of_polygon(const std::vector<glm::vec4>& corners, int width,
                                          int height, double inset_pixels) {
  const glm::vec2 size(static_cast<float>(width), static_cast<float>(height));
  const std::vector<glm::vec2> screen = {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1),
                                         glm::vec2(-1, 1)};
  auto fans = [](const std::vector<std::vector<glm::vec2>>& pieces) {
    std::vector<glm::vec2> triangles;
    for (const auto& piece : pieces) {
      for (size_t k = 1; k + 1 < piece.size(); ++k) {
        triangles.insert(triangles.end(), {piece[0], piece[k], piece[k + 1]});
      }
    }
    return triangles;
  };
  // In front of the near plane (z >= -w), then to pixels.
  const std::vector<glm::vec4> front =
      clip(corners, [](const glm::vec4& p) { return static_cast<double>(p.z + p.w); });
  std::vector<glm::vec2> polygon;
  for (const glm::vec4& p : front) {
    if (p.w <= 0.0f) return fans({screen});
    polygon.push_back((glm::vec2(p) / p.w * 0.5f + 0.5f) * size);
  }
  // Counter-clockwise, and not degenerate.
  double area = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::vec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    area += static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y;
  }
  if (polygon.size() < 3 || std::abs(area) < 1.0) return fans({screen});
  if (area < 0) std::reverse(polygon.begin(), polygon.end());

  // Screen rectangle (a pixel wider on every side) minus the inset polygon: for each edge,
  // the part outside it and inside all earlier ones. The pieces do not overlap.
  std::vector<glm::vec2> rest = {glm::vec2(-1, -1), glm::vec2(size.x + 1, -1),
                                 glm::vec2(size.x + 1, size.y + 1), glm::vec2(-1, size.y + 1)};
  std::vector<std::vector<glm::vec2>> pieces;
  for (size_t i = 0; i < polygon.size() && rest.size() >= 3; ++i) {
    const glm::dvec2 a(polygon[i]), b(polygon[(i + 1) % polygon.size()]);
    const glm::dvec2 edge = b - a;
    const double length = std::sqrt(edge.x * edge.x + edge.y * edge.y);
    if (length < 1e-9) continue;
    const glm::dvec2 inward(-edge.y / length, edge.x / length);  // left of a CCW edge
    const double offset = glm::dot(inward, a) + inset_pixels;
    auto inside = [&](const glm::vec2& p) { return glm::dot(inward, glm::dvec2(p)) - offset; };
    auto outside = [&](const glm::vec2& p) { return offset - glm::dot(inward, glm::dvec2(p)); };
    std::vector<glm::vec2> piece = clip(rest, outside);
    if (piece.size() >= 3) pieces.push_back(std::move(piece));
    rest = clip(rest, inside);
  }
  std::vector<glm::vec2> triangles = fans(pieces);
  for (glm::vec2& p : triangles) p = p / size * 2.0f - 1.0f;
  return triangles;
}

}  // namespace tissu
