// A triangle mesh as the simulator reads it: positions, rest coordinates and triangles.
#pragma once

#include "core/types.h"

namespace tissu {

struct TriMesh {
  Vec3List positions;  // (V) vertex positions, m
  Vec2List rest_uv;    // (V) rest coordinates in the fabric plane, m (u = weft, v = warp)
  TriList triangles;   // (T) vertex ids; counter-clockwise in (u, v)
  bool uv_from_file = false;  // rest_uv came from texture coordinates
};

}  // namespace tissu
