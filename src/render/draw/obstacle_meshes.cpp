#include "render/draw/obstacle_meshes.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "render/draw/view_math.h"

namespace tissu {

namespace {

// Adds a grid of (rows+1) x (columns+1) vertices as quads split into two triangles;
// `at(row, column)` gives the vertex. Rows run in +v, columns in +u; counter-clockwise
// when u x v points outward.
template <class VertexAt>
void add_grid(IndexedMesh& mesh, int rows, int columns, VertexAt at) {
  const uint32_t first = static_cast<uint32_t>(mesh.vertices.size());
  for (int r = 0; r <= rows; ++r) {
    for (int c = 0; c <= columns; ++c) mesh.vertices.push_back(at(r, c));
  }
  const uint32_t stride = static_cast<uint32_t>(columns + 1);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const uint32_t a = first + r * stride + c, b = a + 1, d = a + stride, e = d + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, d});
    }
  }
}

}  // namespace

IndexedMesh unit_sphere(int slices, int stacks) {
  IndexedMesh mesh;
  const float pi = glm::pi<float>();
  // Rows from the south pole up, columns around +z counter-clockwise: u x v points out.
  add_grid(mesh, stacks, slices, [&](int r, int c) {
    const float polar = pi * (1.0f - static_cast<float>(r) / stacks);  // pi at the south pole
    const float azimuth = 2.0f * pi * static_cast<float>(c % slices) / slices;
    const glm::vec3 p(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                      std::cos(polar));
    return MeshVertex{p, p, glm::vec2(0.0f)};
  });
  return mesh;
}

IndexedMesh unit_cylinder(int slices) {
  IndexedMesh mesh;
  const float pi = glm::pi<float>();
  auto around = [&](int c) {
    const float a = 2.0f * pi * static_cast<float>(c % slices) / slices;
    return glm::vec3(std::cos(a), std::sin(a), 0.0f);
  };
  // Side: rows along +z, columns counter-clockwise around +z.
  add_grid(mesh, 1, slices, [&](int r, int c) {
    const glm::vec3 radial = around(c);
    return MeshVertex{radial + glm::vec3(0, 0, r == 0 ? -1.0f : 1.0f), radial, glm::vec2(0.0f)};
  });
  // Caps: a fan around a centre vertex with the flat normal.
  for (float side : {-1.0f, 1.0f}) {
    const glm::vec3 normal(0, 0, side);
    const uint32_t centre = static_cast<uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back({normal, normal, glm::vec2(0.0f)});
    for (int c = 0; c < slices; ++c) {
      mesh.vertices.push_back({around(c) + normal, normal, glm::vec2(0.0f)});
    }
    for (int c = 0; c < slices; ++c) {
      const uint32_t a = centre + 1 + c, b = centre + 1 + (c + 1) % slices;
      if (side > 0) {
        mesh.indices.insert(mesh.indices.end(), {centre, a, b});
      } else {
        mesh.indices.insert(mesh.indices.end(), {centre, b, a});
      }
    }
  }
  return mesh;
}

IndexedMesh unit_square() {
  IndexedMesh mesh;
  const glm::vec3 n(0, 0, 1);
  add_grid(mesh, 1, 1, [&](int r, int c) {
    return MeshVertex{glm::vec3(c ? 1.0f : -1.0f, r ? 1.0f : -1.0f, 0.0f), n, glm::vec2(0.0f)};
  });
  return mesh;
}

IndexedMesh surface_mesh(const Vec3List& vertices, const TriList& triangles) {
  // Angle-weighted vertex normals; a corner whose face turns more than 40 degrees away
  // from its vertex's normal (a crease) keeps the face's own normal.
  std::vector<Vec3> face(triangles.size());
  Vec3List smooth(vertices.size(), Vec3::Zero());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Tri& tri = triangles[t];
    face[t] = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]).normalized();
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = vertices[tri[(k + 1) % 3]] - vertices[tri[k]];
      const Vec3 e2 = vertices[tri[(k + 2) % 3]] - vertices[tri[k]];
      smooth[tri[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * face[t];
    }
  }
  for (Vec3& n : smooth) n.normalize();
  const double crease = std::cos(40.0 * M_PI / 180.0);
  IndexedMesh mesh;
  mesh.vertices.reserve(3 * triangles.size());
  mesh.indices.reserve(3 * triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = triangles[t][k];
      const Vec3& n = smooth[v].dot(face[t]) >= crease ? smooth[v] : face[t];
      mesh.indices.push_back(static_cast<uint32_t>(mesh.vertices.size()));
      mesh.vertices.push_back({to_glm(vertices[v]), to_glm(n), glm::vec2(0.0f)});
    }
  }
  return mesh;
}

glm::mat4 obstacle_model(const ObstacleShape& shape, const glm::vec3& plane_focus,
                         float plane_half_size) {
  const glm::vec3 center = to_glm(shape.center);
  const float r = static_cast<float>(shape.radius);
  switch (shape.kind) {
    case ObstacleShape::Kind::Sphere:
      return glm::scale(glm::translate(glm::mat4(1.0f), center), glm::vec3(r));
    case ObstacleShape::Kind::Cylinder: {
      const glm::mat4 rotation(rotation_from_z(to_glm(shape.axis)));
      return glm::scale(glm::translate(glm::mat4(1.0f), center) * rotation,
                        glm::vec3(r, r, static_cast<float>(shape.half_length)));
    }
    case ObstacleShape::Kind::Mesh: {
      glm::mat4 rotation(1.0f);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) rotation[j][i] = static_cast<float>(shape.rotation(i, j));
      }
      return glm::translate(glm::mat4(1.0f), center) * rotation *
             glm::translate(glm::mat4(1.0f), -to_glm(shape.pivot));
    }
    case ObstacleShape::Kind::Plane:
    default: {
      const glm::vec3 n = glm::normalize(to_glm(shape.axis));
      const glm::vec3 foot = plane_focus - glm::dot(plane_focus - center, n) * n;
      const glm::mat4 rotation(rotation_from_z(n));
      return glm::scale(glm::translate(glm::mat4(1.0f), foot) * rotation,
                        glm::vec3(plane_half_size, plane_half_size, 1.0f));
    }
  }
}

}  // namespace tissu
