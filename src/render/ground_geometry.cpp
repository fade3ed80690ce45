#include "render/ground_geometry.h"

#include <algorithm>
#include <cmath>

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

std::optional<GroundRect> shadow_footprint(const Box3& casters, const Vec3& direction,
                                           double height, double margin) {
  if (casters.isEmpty()) return std::nullopt;
  const Vec3 d = direction.normalized();
  if (!(d.z() < -1e-6)) return std::nullopt;
  GroundRect r{glm::dvec2(1e300), glm::dvec2(-1e300)};
  for (const Vec3& c : box_corners(casters)) {
    // Along the light to the plane (corners below the plane project back up: still a bound).
    const Vec3 p = c + d * ((height - c.z()) / d.z());
    r.min = glm::min(r.min, glm::dvec2(p.x(), p.y()));
    r.max = glm::max(r.max, glm::dvec2(p.x(), p.y()));
  }
  r.min -= glm::dvec2(margin);
  r.max += glm::dvec2(margin);
  return r;
}

IndexedMesh ground_mesh(const GroundRect& square, double height) {
  IndexedMesh mesh;
  const glm::vec3 n(0, 0, 1);
  const float z = static_cast<float>(height);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      mesh.vertices.push_back({glm::vec3(static_cast<float>(i ? square.max.x : square.min.x),
                                         static_cast<float>(j ? square.max.y : square.min.y), z),
                               n, glm::vec2(0.0f)});
    }
  }
  mesh.indices = {0, 1, 3, 0, 3, 2};
  return mesh;
}

SplitGround split_ground(const GroundRect& square, double height, const GroundRect& inner) {
  SplitGround split;
  const glm::dvec2 lo = glm::clamp(inner.min, square.min, square.max);
  const glm::dvec2 hi = glm::clamp(inner.max, square.min, square.max);
  if (!(lo.x < hi.x && lo.y < hi.y)) {
    split.outer = ground_mesh(square, height);
    return split;
  }
  const float xs[4] = {static_cast<float>(square.min.x), static_cast<float>(lo.x),
                       static_cast<float>(hi.x), static_cast<float>(square.max.x)};
  const float ys[4] = {static_cast<float>(square.min.y), static_cast<float>(lo.y),
                       static_cast<float>(hi.y), static_cast<float>(square.max.y)};
  const glm::vec3 n(0, 0, 1);
  const float z = static_cast<float>(height);
  std::vector<MeshVertex> grid;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) grid.push_back({glm::vec3(xs[i], ys[j], z), n, glm::vec2(0.0f)});
  }
  split.outer.vertices = grid;
  split.inner.vertices = grid;
  for (uint32_t j = 0; j < 3; ++j) {
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t a = j * 4 + i, b = a + 1, c = a + 4, d = c + 1;
      // Cells of zero width (the footprint reaching the square's edge) are left out.
      if (xs[i] == xs[i + 1] || ys[j] == ys[j + 1]) continue;
      IndexedMesh& mesh = (i == 1 && j == 1) ? split.inner : split.outer;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  return split;
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
