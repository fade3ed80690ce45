// A triangle mesh as the simulator reads it: positions, rest coordinates and triangles.
#pragma once

#include "core/types.h"

namespace tissu {

struct TriMesh {
  Vec3List positions;  // (V) vertex positions, m
  Vec2List rest_uv;    // (V) rest coordinates in the fabric plane, m (u = weft, v = warp)
  TriList triangles;   // (T) vertex ids; counter-clockwise in (u, v)
  bool uv_from_file = false;  // rest_uv came from texture coordinates
  // Vertex i is the file's i-th vertex (false when the reader welded corners that the file
  // stores apart, as STL does: then vertex ids are not the file's and pins by id are refused).
  bool file_vertex_ids = true;
};

}  // namespace tissu
