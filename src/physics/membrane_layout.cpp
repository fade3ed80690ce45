#include "physics/membrane_layout.h"

#include <limits>
#include <stdexcept>

#include "physics/model.h"

namespace tissu {

MembraneLayout build_membrane_layout(const TriList& triangles,
                                     const std::vector<TriangleRest>& rest, uint64_t mesh_id) {
  const size_t n = triangles.size();
  MembraneLayout l;
  l.num_triangles = static_cast<int>(n);
  l.mesh_id = mesh_id;
  const size_t size = n + MembraneLayout::kPadding;
  for (auto* column : {&l.ru0, &l.ru1, &l.ru2, &l.rv0, &l.rv1, &l.rv2, &l.area}) {
    column->assign(size, 0.0);
  }
  for (auto* column : {&l.a, &l.b, &l.c}) column->assign(size, 0);
  constexpr int kMaxVertex = std::numeric_limits<int32_t>::max() / 3;
  for (size_t t = 0; t < n; ++t) {
    if (triangles[t].maxCoeff() > kMaxVertex) {
      throw std::length_error("membrane layout: vertex ids above 715 million");
    }
    const TriangleRest& r = rest[t];
    l.ru0[t] = r.ru[0];
    l.ru1[t] = r.ru[1];
    l.ru2[t] = r.ru[2];
    l.rv0[t] = r.rv[0];
    l.rv1[t] = r.rv[1];
    l.rv2[t] = r.rv[2];
    l.area[t] = r.area;
    l.a[t] = 3 * triangles[t][0];
    l.b[t] = 3 * triangles[t][1];
    l.c[t] = 3 * triangles[t][2];
  }
  return l;
}

}  // namespace tissu
