// Cloth triangles as the GPU draws them: vertex normals recomputed every frame; shared
// vertices drawn with indices, or, for the wireframe, three corners per triangle (the
// shaders derive barycentric coordinates from the corner index).
#pragma once

#include <vector>

#include "render/frame_content.h"
#include "render/gl/mesh_buffer.h"

namespace tissu {

// Unit vertex normals, each the area-weighted mean of the adjacent triangle normals
// (front side = counter-clockwise). Vertices of no (or only degenerate) triangles get zero.
Vec3List vertex_normals(const Vec3List& positions, const TriList& triangles);

// Throws RenderError when triangles index missing vertices or rest_uv does not match.
void check_cloth(const FrameContent& content);

// The corners of every cloth triangle, with smooth normals and rest (u, v) (for the
// wireframe, which needs corners of its own).
void cloth_corners(const FrameContent& content, std::vector<MeshVertex>& corners);

// Shared vertices: positions and smooth normals (every frame), and the triangles as
// indices and the rest (u, v) per vertex (zeros when the content has none).
void cloth_vertices(const FrameContent& content, std::vector<ClothVertex>& vertices);
void cloth_topology(const FrameContent& content, std::vector<uint32_t>& indices,
                    std::vector<glm::vec2>& uv);

}  // namespace tissu
