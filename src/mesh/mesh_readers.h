// File readers behind load_mesh (internal to the mesh module).
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace tissu {

struct MeshFileData {
  // positions and triangles; when mesh.uv_from_file, rest_uv holds the file's texture
  // coordinates (not yet scaled; (0, 0) for vertices no face uses), else rest_uv is empty.
  TriMesh mesh;
  std::vector<std::string> triangle_places;  // where each triangle is in the file
};

// Wavefront OBJ, parsed here so that vertex i is the file's i-th `v` line. Reads v, vt and
// f (v, v/vt, v/vt/vn, v//vn corners; negative indices count back); polygons are split into
// a fan from their first corner; other statements are ignored.
// With `texture` false, texture coordinates are not read (mesh obstacles need none).
MeshFileData read_obj(const std::string& path, bool texture = true);

// Any other format assimp reads, triangulated and with node transforms applied. Corners at
// exactly the same position are welded into one vertex (formats such as STL store a vertex
// per corner); vertices are numbered in order of first appearance.
// assimp runs in a child process (isolated_read.cpp): when it does not finish within the
// time limit (mesh_read_timeout) or dies of a signal, the child is killed and an InputError
// names the file and the problem. The result is the same as read_with_assimp_in_process.
MeshFileData read_with_assimp(const std::string& path, bool texture = true);

// The same read in this process, without a time limit (what the child runs).
MeshFileData read_with_assimp_in_process(const std::string& path, bool texture = true);

// The child's time limit for reading a file of `bytes` bytes, s: 10 s + 1 s per started MiB,
// or the environment variable TISSU_MESH_READ_TIMEOUT (s, a positive number) when set.
double mesh_read_timeout(unsigned long long bytes);

// True when two texture coordinates are the same up to rounding (`extent`: largest |uv|).
bool same_texture_coordinates(const Vec2& a, const Vec2& b, double extent);

// What a UV-seam error adds after naming the vertex.
extern const char* const kSeamAdvice;

}  // namespace tissu
