// Reading a cloth mesh from a file.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace tissu {

// Reads any triangle or polygon mesh format assimp reads (polygons are triangulated).
// Vertex numbering: for .obj files (parsed here, not by assimp), vertex id i is the file's
// (i+1)-th `v` line, including vertices no face uses; for other formats, corners at exactly
// the same position are welded and vertices are numbered in order of first appearance.
// Rest (u, v): the file's texture coordinates times uv_scale (so uv_scale converts texture
// units to m; 1 when they are in m); without texture coordinates, the mesh must be flat and
// is projected onto its plane (see set_rest_uv_from_plane). The result passes validate_mesh.
// Bad input raises InputError naming the file and the place.
TriMesh load_mesh(const std::string& path, double uv_scale);

// A surface read for a mesh obstacle: positions (in the file's units) and triangles, no
// rest coordinates (texture coordinates are ignored). Polygons are split into fans;
// numbering as load_mesh. `places` names each triangle's face in the file, for messages.
struct SurfaceFile {
  Vec3List positions;
  TriList triangles;
  std::vector<std::string> places;
};
// Reads OBJ, OFF, PLY, STL and the other formats assimp reads. Bad input raises
// InputError naming the file and the place; the surface's shape is checked by its user
// (collision/closed_surface.h).
SurfaceFile load_surface(const std::string& path);

// Relative flatness tolerance: distance to the plane / bounding-box diagonal.
constexpr double kFlatTolerance = 1e-6;

// Sets rest_uv of a flat mesh to its positions (m) in the frame of its plane: the normal n
// is the area-weighted mean triangle normal (so consistently ordered triangles come out
// counter-clockwise), u is the world x axis projected onto the plane (world y when x is
// within about 6 degrees of n), v = n x u; coordinates are measured from the world origin,
// so a mesh in the x-y plane facing +z gets (u, v) = (x, y). Throws InputError when a vertex
// lies farther than kFlatTolerance * (bounding-box diagonal) from the plane.
void set_rest_uv_from_plane(TriMesh& mesh, const std::string& source_name);

}  // namespace tissu
