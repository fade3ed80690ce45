#include "mesh/validate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/quality.h"

namespace tissu {
namespace {

class Checker {
 public:
  Checker(TriMesh& mesh, const std::string& source, std::vector<std::string>& places)
      : mesh_(mesh), source_(source), places_(places) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(source_ + ": " + problem);
  }
  [[noreturn]] void fail_at(size_t t, const std::string& problem) const {
    fail(place(t) + ": " + problem);
  }
  void warn(const std::string& problem) const {
    std::cerr << "warning: " << source_ << ": " << problem << "\n";
  }
  std::string place(size_t t) const {
    return places_.empty() ? "triangle " + std::to_string(t) : places_[t];
  }

  void sizes() const {
    if (mesh_.positions.size() != mesh_.rest_uv.size()) {
      fail(std::to_string(mesh_.positions.size()) + " positions but " +
           std::to_string(mesh_.rest_uv.size()) + " rest coordinates");
    }
    if (!places_.empty() && places_.size() != mesh_.triangles.size()) {
      fail("internal: triangle names do not match the triangles");
    }
    if (mesh_.triangles.empty()) fail("contains no triangles");
  }

  void finite_coordinates() const {
    for (size_t v = 0; v < mesh_.positions.size(); ++v) {
      if (!mesh_.positions[v].allFinite()) {
        fail("vertex id " + std::to_string(v) + ": non-finite position " +
             format_short(mesh_.positions[v]));
      }
      if (!mesh_.rest_uv[v].allFinite()) {
        fail("vertex id " + std::to_string(v) + ": non-finite rest coordinates " +
             format_short(mesh_.rest_uv[v]));
      }
    }
  }

  void vertex_ids() const {
    const long long count = static_cast<long long>(mesh_.positions.size());
    for (size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const Tri& tri = mesh_.triangles[t];
      for (int k = 0; k < 3; ++k) {
        if (tri[k] < 0 || tri[k] >= count) {
          fail_at(t, "vertex id " + std::to_string(tri[k]) + " out of range (mesh has " +
                         std::to_string(count) + " vertices)");
        }
      }
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
        fail_at(t, "uses a vertex twice (vertex ids " + vertex_list(tri) + ")");
      }
    }
  }

  void drop_duplicates() {
    // Triangles sorted by their vertex set (then by position in the list): the first of
    // each run of equal sets is kept.
    const size_t count = mesh_.triangles.size();
    std::vector<std::pair<std::array<int, 3>, size_t>> keys(count);
    for (size_t t = 0; t < count; ++t) {
      const Tri& tri = mesh_.triangles[t];
      keys[t] = {{tri[0], tri[1], tri[2]}, t};
      std::sort(keys[t].first.begin(), keys[t].first.end());
    }
    std::sort(keys.begin(), keys.end());
    std::vector<char> keep(count, 1);
    size_t dropped = 0, example = 0, example_of = 0;
    for (size_t k = 1; k < count; ++k) {
      if (keys[k].first != keys[k - 1].first) continue;
      const size_t t = keys[k].second;
      keep[t] = 0;
      size_t first = k - 1;
      while (first > 0 && keys[first - 1].first == keys[k].first) --first;
      if (dropped++ == 0 || t < example) {
        example = t;
        example_of = keys[first].second;
      }
    }
    if (dropped == 0) return;
    warn("dropped " + std::to_string(dropped) + " duplicate triangle" + (dropped > 1 ? "s" : "") +
         " (first: " + place(example) + " repeats " + place(example_of) + ")");
    TriList kept;
    std::vector<std::string> kept_places;
    for (size_t t = 0; t < count; ++t) {
      if (!keep[t]) continue;
      kept.push_back(mesh_.triangles[t]);
      if (!places_.empty()) kept_places.push_back(std::move(places_[t]));
    }
    mesh_.triangles = std::move(kept);
    places_ = std::move(kept_places);
  }

  void nonzero_areas() const {
    for (size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const Tri& tri = mesh_.triangles[t];
      const Vec3 &a = mesh_.positions[tri[0]], &b = mesh_.positions[tri[1]],
                 &c = mesh_.positions[tri[2]];
      const double area3 = 0.5 * (b - a).cross(c - a).norm();
      const double longest3 =
          std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      if (!(area3 > kZeroAreaRatio * longest3)) {
        fail_at(t, "zero area in 3D (vertex ids " + vertex_list(tri) + ", area " +
                       format_short(area3) + " m^2)");
      }
      const Vec2 &p = mesh_.rest_uv[tri[0]], &q = mesh_.rest_uv[tri[1]], &r = mesh_.rest_uv[tri[2]];
      const double area2 = std::abs(uv_area(mesh_, tri));
      const double longest2 =
          std::max({(q - p).squaredNorm(), (r - q).squaredNorm(), (p - r).squaredNorm()});
      if (!(area2 > kZeroAreaRatio * longest2)) {
        fail_at(t, "zero area in (u, v) (vertex ids " + vertex_list(tri) + ", area " +
                       format_short(area2) + " m^2)");
      }
    }
  }

  void orientation() {
    size_t clockwise = 0, first_clockwise = 0, first_ccw = 0;
    for (size_t t = mesh_.triangles.size(); t-- > 0;) {
      if (uv_area(mesh_, mesh_.triangles[t]) < 0) {
        ++clockwise;
        first_clockwise = t;
      } else {
        first_ccw = t;
      }
    }
    const size_t total = mesh_.triangles.size();
    if (clockwise == total) {
      warn("all triangles are clockwise in (u, v); reversed them all");
      for (Tri& tri : mesh_.triangles) std::swap(tri[1], tri[2]);
    } else if (clockwise > 0) {
      const bool fewer_cw = 2 * clockwise <= total;
      const size_t t = fewer_cw ? first_clockwise : first_ccw;
      const size_t others = fewer_cw ? total - clockwise : clockwise;
      fail_at(t, std::string(fewer_cw ? "clockwise" : "counter-clockwise") + " in (u, v) but " +
                     std::to_string(others) + " of " + std::to_string(total) +
                     " triangles are the other way (the rest shape folds over itself or the "
                     "triangles are inconsistently ordered)");
    }
  }

  void unused_vertices() const {
    std::vector<char> used(mesh_.positions.size(), 0);
    for (const Tri& tri : mesh_.triangles) used[tri[0]] = used[tri[1]] = used[tri[2]] = 1;
    const size_t unused = std::count(used.begin(), used.end(), 0);
    if (unused == 0) return;
    const size_t first = std::find(used.begin(), used.end(), 0) - used.begin();
    warn(std::to_string(unused) + (unused > 1 ? " vertices are" : " vertex is") +
         " used by no triangle (first: vertex id " + std::to_string(first) + "); kept");
  }

 private:
  static std::string vertex_list(const Tri& tri) {
    return std::to_string(tri[0]) + ", " + std::to_string(tri[1]) + ", " + std::to_string(tri[2]);
  }

  TriMesh& mesh_;
  const std::string& source_;
  std::vector<std::string>& places_;
};

}  // namespace

void validate_mesh(TriMesh& mesh, const std::string& source_name,
                   std::vector<std::string> triangle_places) {
  Checker check(mesh, source_name, triangle_places);
  check.sizes();
  check.finite_coordinates();
  check.vertex_ids();
  check.drop_duplicates();
  check.nonzero_areas();
  check.orientation();
  check.unused_vertices();
}

}  // namespace tissu
