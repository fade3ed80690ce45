#include "render/gl/mesh_buffer.h"

#include <cstddef>

namespace tissu {

MeshBuffer::MeshBuffer()
    : vao_(make_vertex_array()), vertices_(make_buffer()), indices_(make_buffer()) {
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  const GLsizei stride = sizeof(MeshVertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(MeshVertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(MeshVertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(MeshVertex, uv)));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_.get());  // recorded in the VAO
  glBindVertexArray(0);
}

void MeshBuffer::upload(const IndexedMesh& mesh) {
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  glBufferData(GL_ARRAY_BUFFER, mesh.vertices.size() * sizeof(MeshVertex), mesh.vertices.data(),
               GL_STATIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.size() * sizeof(uint32_t),
               mesh.indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  count_ = static_cast<GLsizei>(mesh.indices.size());
  indexed_ = true;
}

void MeshBuffer::upload_triangles(const std::vector<MeshVertex>& corners) {
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  glBufferData(GL_ARRAY_BUFFER, corners.size() * sizeof(MeshVertex), corners.data(),
               GL_STREAM_DRAW);
  count_ = static_cast<GLsizei>(corners.size());
  indexed_ = false;
}

void MeshBuffer::draw() const {
  if (count_ == 0) return;
  glBindVertexArray(vao_.get());
  if (indexed_) {
    glDrawElements(GL_TRIANGLES, count_, GL_UNSIGNED_INT, nullptr);
  } else {
    glDrawArrays(GL_TRIANGLES, 0, count_);
  }
  glBindVertexArray(0);
}

ClothBuffer::ClothBuffer()
    : vao_(make_vertex_array()), vertices_(make_buffer()), uv_(make_buffer()), indices_(make_buffer()) {
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  const GLsizei stride = sizeof(ClothVertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(ClothVertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(ClothVertex, normal)));
  glBindBuffer(GL_ARRAY_BUFFER, uv_.get());
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_.get());  // recorded in the VAO
  glBindVertexArray(0);
}

void ClothBuffer::set_topology(const std::vector<uint32_t>& indices,
                               const std::vector<glm::vec2>& uv) {
  if (indices != indices_uploaded_) {
    glBindVertexArray(vao_.get());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(uint32_t), indices.data(),
                 GL_STATIC_DRAW);
    glBindVertexArray(0);
    indices_uploaded_ = indices;
  }
  if (uv != uv_uploaded_) {
    glBindBuffer(GL_ARRAY_BUFFER, uv_.get());
    glBufferData(GL_ARRAY_BUFFER, uv.size() * sizeof(glm::vec2), uv.data(), GL_STATIC_DRAW);
    uv_uploaded_ = uv;
  }
  count_ = static_cast<GLsizei>(indices.size());
}

void ClothBuffer::upload_vertices(const std::vector<ClothVertex>& vertices) {
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  // Same size every frame: respecify (lets the driver hand out fresh memory while the
  // previous frame may still be read), then fill.
  glBufferData(GL_ARRAY_BUFFER, vertices.size() * sizeof(ClothVertex), vertices.data(),
               GL_STREAM_DRAW);
}

void ClothBuffer::draw() const {
  if (count_ == 0) return;
  glBindVertexArray(vao_.get());
  glDrawElements(GL_TRIANGLES, count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace tissu
