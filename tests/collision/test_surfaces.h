// Closed surfaces built inside the collision tests: an icosphere and an axis-aligned box.
#pragma once

#include <map>
#include <utility>

#include "core/types.h"

namespace tissu::testing {

struct SurfaceData {
  Vec3List vertices;
  TriList triangles;  // counter-clockwise seen from outside
};

// Icosahedron subdivided `levels` times, vertices on the sphere of `radius` around `centre`.
inline SurfaceData icosphere(int levels, double radius, const Vec3& centre = Vec3::Zero()) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  SurfaceData s;
  s.vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3& v : s.vertices) v.normalize();
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      s.vertices.push_back((s.vertices[a] + s.vertices[b]).normalized());
      return middle[key] = static_cast<int>(s.vertices.size()) - 1;
    };
    TriList finer;
    for (const Tri& t : s.triangles) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.emplace_back(t[0], ab, ca);
      finer.emplace_back(t[1], bc, ab);
      finer.emplace_back(t[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    s.triangles = finer;
  }
  for (Vec3& v : s.vertices) v = centre + radius * v;
  return s;
}

// The box [lo, hi] as 12 triangles.
inline SurfaceData box_surface(const Vec3& lo, const Vec3& hi) {
  SurfaceData s;
  for (int k = 0; k < 8; ++k) {
    s.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                            k & 4 ? hi.z() : lo.z());
  }
  // Each face as two triangles, counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.emplace_back(q[0], q[1], q[2]);
    s.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return s;
}

}  // namespace tissu::testing
