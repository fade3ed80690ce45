// Triangle meshes on the CPU and their GPU buffers. Vertex attributes:
// location 0 position, 1 normal, 2 uv (the shaders declare the same locations).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "render/gl/gl_objects.h"

namespace tissu {

struct MeshVertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};

struct IndexedMesh {
  std::vector<MeshVertex> vertices;
  std::vector<uint32_t> indices;  // three per triangle, counter-clockwise seen from outside
};

class MeshBuffer {
 public:
  MeshBuffer();
  // Static geometry drawn with indices.
  void upload(const IndexedMesh& mesh);
  // Geometry that changes every frame, drawn as consecutive triangles (no indices).
  void upload_triangles(const std::vector<MeshVertex>& corners);
  void draw() const;
  bool empty() const { return count_ == 0; }

 private:
  GlVertexArray vao_;
  GlBuffer vertices_, indices_;
  GLsizei count_ = 0;
  bool indexed_ = false;
};

// The cloth drawn with shared vertices and indices: the triangles and rest (u, v) are
// uploaded when they change (once per run), positions and normals every frame.
struct ClothVertex {
  glm::vec3 position;
  glm::vec3 normal;
};

class ClothBuffer {
 public:
  ClothBuffer();
  // `uv` may be empty (no pattern): zeros are used. Skips the upload when unchanged.
  void set_topology(const std::vector<uint32_t>& indices, const std::vector<glm::vec2>& uv);
  void upload_vertices(const std::vector<ClothVertex>& vertices);
  void draw() const;
  bool empty() const { return count_ == 0; }

 private:
  GlVertexArray vao_;
  GlBuffer vertices_, uv_, indices_;
  std::vector<uint32_t> indices_uploaded_;
  std::vector<glm::vec2> uv_uploaded_;
  GLsizei count_ = 0;
};

}  // namespace tissu
