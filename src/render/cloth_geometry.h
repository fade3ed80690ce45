// Cloth triangles as the GPU draws them: vertex normals recomputed every frame,
// then three corners per triangle (the shaders derive barycentric coordinates for
// the wireframe from the corner index, so corners are not shared).
#pragma once

#include <vector>

#include "render/frame_content.h"
#include "render/mesh_buffer.h"

namespace tissu {

// Unit vertex normals, each the area-weighted mean of the adjacent triangle normals
// (front side = counter-clockwise). Vertices of no (or only degenerate) triangles get zero.
Vec3List vertex_normals(const Vec3List& positions, const TriList& triangles);

// Throws RenderError when triangles index missing vertices or rest_uv does not match.
void check_cloth(const FrameContent& content);

// The corners of every cloth triangle, with smooth normals and rest (u, v).
void cloth_corners(const FrameContent& content, std::vector<MeshVertex>& corners);

}  // namespace tissu
