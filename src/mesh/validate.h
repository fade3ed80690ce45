// Checks a mesh before simulation; shared by the file loader and the generators.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace tissu {

// Two triangles below this area / (longest edge)^2 count as zero-area: about a relative
// height of 1e-12, i.e. collinear up to rounding. (Equilateral: 0.43.)
constexpr double kZeroAreaRatio = 1e-12;

// Rejects with InputError ("<source_name>: <place>: <problem>", one line):
//   positions and rest_uv of different lengths, no triangles, a vertex id out of range or
//   repeated in a triangle, a non-finite position or rest coordinate, a triangle of zero
//   area in 3D or in (u, v), and triangles of opposite orientations in (u, v) (a fold).
// Repairs, with one warning line each on stderr:
//   duplicate triangles (same three vertices in any order): later copies are dropped;
//   all triangles clockwise in (u, v): every triangle is reversed.
// Warns about vertices used by no triangle and keeps them.
// `triangle_places` names each triangle for messages (e.g. "line 17 (face 12)"); when
// empty, triangles are named "triangle <id>" (0-based). Vertices are named "vertex id <id>"
// (0-based, as the simulator numbers them; for an OBJ file, the 1-based index minus 1).
void validate_mesh(TriMesh& mesh, const std::string& source_name,
                   std::vector<std::string> triangle_places = {});

}  // namespace tissu
