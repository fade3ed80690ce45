// Shape quality of a mesh's rest triangles, measured in (u, v).
#pragma once

#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace tissu {

struct MeshQuality {
  int vertex_count = 0;
  int triangle_count = 0;
  double min_angle_deg = 0;             // smallest angle of any triangle
  double max_angle_deg = 0;             // largest angle of any triangle
  double mean_angle_deviation_deg = 0;  // mean of |angle - 60 deg| over all angles
  // Aspect ratio: longest edge / shortest altitude * sqrt(3) / 2, so 1 for an equilateral
  // triangle, 1.73 for a right isosceles one, about 87 for a right triangle with legs 1:100.
  double max_aspect_ratio = 0;
  double mean_aspect_ratio = 0;
  double min_area = 0;    // m^2
  double max_area = 0;    // m^2
  double total_area = 0;  // m^2, signed areas summed (triangles are counter-clockwise)
  // [k] = number of interior (not boundary) vertices with k neighbours.
  std::vector<int> interior_valence_histogram;
  double interior_valence6_fraction = 0;
  // Fraction of edges whose direction (mod 180 deg) falls in the 4 fullest of 36 bins of
  // 5 deg: 1 for a grid (0, 45, 90, 135 deg), about 0.11 to 0.2 for an isotropic mesh.
  double edge_direction_concentration = 0;
};

MeshQuality measure_quality(const TriMesh& mesh);

// Edges used by exactly one triangle, each as (a, b) in that triangle's order.
std::vector<std::pair<int, int>> boundary_edges(const TriList& triangles);

// Signed area (m^2) of the triangle in (u, v); positive when counter-clockwise.
double uv_area(const TriMesh& mesh, const Tri& t);

}  // namespace tissu
