#include "render/draw/cloth_geometry.h"

#include <string>

#include "render/draw/view_math.h"
#include "render/render_error.h"

namespace tissu {

Vec3List vertex_normals(const Vec3List& positions, const TriList& triangles) {
  Vec3List normals(positions.size(), Vec3::Zero());
  for (const Tri& t : triangles) {
    // The cross product's length is twice the area: summing it weights by area.
    const Vec3 n = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (Vec3& n : normals) {
    const double length = n.norm();
    n = length > 0 ? Vec3(n / length) : Vec3::Zero();
  }
  return normals;
}

void check_cloth(const FrameContent& content) {
  const size_t n = content.positions.size();
  if (!content.rest_uv.empty() && content.rest_uv.size() != n) {
    throw RenderError("frame content: " + std::to_string(content.rest_uv.size()) +
                      " rest_uv entries for " + std::to_string(n) + " cloth vertices");
  }
  for (size_t i = 0; i < content.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int v = content.triangles[i][k];
      if (v < 0 || static_cast<size_t>(v) >= n) {
        throw RenderError("frame content: triangle " + std::to_string(i) + " uses vertex " +
                          std::to_string(v) + " of " + std::to_string(n));
      }
    }
  }
}

void cloth_corners(const FrameContent& content, std::vector<MeshVertex>& corners) {
  const Vec3List normals = vertex_normals(content.positions, content.triangles);
  const bool has_uv = !content.rest_uv.empty();
  corners.resize(content.triangles.size() * 3);
  size_t c = 0;
  for (const Tri& t : content.triangles) {
    for (int k = 0; k < 3; ++k, ++c) {
      const int v = t[k];
      corners[c].position = to_glm(content.positions[v]);
      corners[c].normal = to_glm(normals[v]);
      corners[c].uv = has_uv ? glm::vec2(static_cast<float>(content.rest_uv[v].x()),
                                         static_cast<float>(content.rest_uv[v].y()))
                             : glm::vec2(0.0f);
    }
  }
}

void cloth_vertices(const FrameContent& content, std::vector<ClothVertex>& vertices) {
  const Vec3List normals = vertex_normals(content.positions, content.triangles);
  vertices.resize(content.positions.size());
  for (size_t v = 0; v < vertices.size(); ++v) {
    vertices[v].position = to_glm(content.positions[v]);
    vertices[v].normal = to_glm(normals[v]);
  }
}

void cloth_topology(const FrameContent& content, std::vector<uint32_t>& indices,
                    std::vector<glm::vec2>& uv) {
  indices.resize(content.triangles.size() * 3);
  size_t c = 0;
  for (const Tri& t : content.triangles) {
    for (int k = 0; k < 3; ++k) indices[c++] = static_cast<uint32_t>(t[k]);
  }
  uv.assign(content.positions.size(), glm::vec2(0.0f));
  for (size_t v = 0; v < content.rest_uv.size() && v < uv.size(); ++v) {
    uv[v] = glm::vec2(static_cast<float>(content.rest_uv[v].x()),
                      static_cast<float>(content.rest_uv[v].y()));
  }
}

}  // namespace tissu
