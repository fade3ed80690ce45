#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/mesh_readers.h"

namespace tissu {
namespace {

std::string place_of(unsigned mesh, unsigned face) {
  return "mesh " + std::to_string(mesh) + ", face " + std::to_string(face);
}

// assimp 5.2's PLY reader never returns on a header without an end_header line or with a
// NUL byte in it, and misreads NUL bytes in an ASCII body into faces that make its
// triangulation abort: such files are rejected before assimp reads them.
void check_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // By name or by content, either way assimp reads it as PLY.
  auto lower = [](std::string t) {
    for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  const bool ply_name = path.size() >= 4 && lower(path.substr(path.size() - 4)) == ".ply";
  if (!ply_name && lower(text.substr(0, 3)) != "ply") return;
  auto fail = [&](const std::string& problem) { throw InputError(path + ": " + problem); };
  const size_t end = std::min(text.find("\nend_header\n"), text.find("\nend_header\r\n"));
  if (end == std::string::npos) fail("PLY header: no end_header line");
  const size_t nul = text.find('\0');
  if (nul < end) fail("byte " + std::to_string(nul) + ": NUL byte in the PLY header");
  if (nul != std::string::npos && text.find("\nformat ascii") < end) {
    fail("byte " + std::to_string(nul) + ": NUL byte in an ASCII PLY file");
  }
  // Every header line must be a PLY statement: the reader also loops forever on some
  // malformed ones ("property float oat z").
  static const std::set<std::string> kTypes = {
      "char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
      "int16", "uint16", "int32", "uint32", "float32", "float64"};
  auto is_count = [](const std::string& w) {
    return !w.empty() && w.size() < 19 &&
           std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  std::istringstream header(text.substr(0, end));
  int number = 0;
  for (std::string line; std::getline(header, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream in_line(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(in_line),
                               std::istream_iterator<std::string>()};
    const bool ok =
        (number == 1 && w.size() == 1 && w[0] == "ply") ||
        (number > 1 && !w.empty() && (w[0] == "comment" || w[0] == "obj_info")) ||
        (number > 1 && w.size() == 3 && w[0] == "format" && w[2] == "1.0" &&
         (w[1] == "ascii" || w[1] == "binary_little_endian" || w[1] == "binary_big_endian")) ||
        (number > 1 && w.size() == 3 && w[0] == "element" && is_count(w[2])) ||
        (number > 1 && w.size() == 3 && w[0] == "property" && kTypes.count(w[1])) ||
        (number > 1 && w.size() == 5 && w[0] == "property" && w[1] == "list" &&
         kTypes.count(w[2]) && kTypes.count(w[3]));
    const bool printable = std::all_of(line.begin(), line.end(), [](char c) {
      return c == ' ' || c == '\t' || (c > 0x20 && c < 0x7f);
    });
    if (!ok || !printable) {
      fail("PLY header line " + std::to_string(number) + ": not a PLY header statement");
    }
  }
}

}  // namespace

MeshFileData read_with_assimp_in_process(const std::string& path, bool texture) {
  auto fail = [&](const std::string& problem) { throw InputError(path + ": " + problem); };
  check_ply(path);
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_ValidateDataStructure | aiProcess_PreTransformVertices);
  if (!scene || !scene->mRootNode) {
    std::string reason = importer.GetErrorString();
    if (!reason.empty() && reason.back() == '\n') reason.pop_back();
    fail("cannot read this format or file: " + reason);
  }

  // Texture coordinates come from channel 0, and only when every mesh has them.
  bool with_texture = texture && scene->mNumMeshes > 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    with_texture = with_texture && scene->mMeshes[m]->HasTextureCoords(0);
  }

  MeshFileData data;
  TriMesh& mesh = data.mesh;
  mesh.uv_from_file = with_texture;
  // Faces first: indices in range and corner positions finite, named by face.
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* source = scene->mMeshes[m];
    for (unsigned f = 0; f < source->mNumFaces; ++f) {
      const aiFace& face = source->mFaces[f];
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        const unsigned corner = face.mIndices[k];
        if (corner >= source->mNumVertices) {
          fail(place_of(m, f) + ": vertex index " + std::to_string(corner) +
               " out of range (mesh has " + std::to_string(source->mNumVertices) + " vertices)");
        }
        const aiVector3D& p = source->mVertices[corner];
        const Vec3 position(p.x, p.y, p.z);
        if (!position.allFinite()) {
          fail(place_of(m, f) + ": non-finite position " + format_short(position));
        }
      }
    }
  }

  // Vertices in the order of the file's vertex list (assimp keeps it for PLY and OFF),
  // mesh after mesh; a vertex at exactly the position of an earlier one is welded to it
  // (formats such as STL store a vertex per corner), and then ids are no longer the file's.
  std::map<std::array<double, 3>, int> id_at;
  std::vector<std::string> first_place;  // where each vertex got its (u, v)
  std::vector<std::vector<int>> id_of(scene->mNumMeshes);
  double extent = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* source = scene->mMeshes[m];
    id_of[m].resize(source->mNumVertices);
    for (unsigned v = 0; v < source->mNumVertices; ++v) {
      const aiVector3D& p = source->mVertices[v];
      const Vec3 position(p.x, p.y, p.z);
      const std::string place = "mesh " + std::to_string(m) + ", vertex " + std::to_string(v);
      if (!position.allFinite()) fail(place + ": non-finite position " + format_short(position));
      const auto [it, is_new] =
          id_at.emplace(std::array<double, 3>{position.x(), position.y(), position.z()},
                        static_cast<int>(mesh.positions.size()));
      const int id = it->second;
      id_of[m][v] = id;
      if (is_new) {
        mesh.positions.push_back(position);
      } else {
        mesh.file_vertex_ids = false;
      }
      if (!with_texture) continue;
      const aiVector3D& t = source->mTextureCoords[0][v];
      const Vec2 uv(t.x, t.y);
      if (is_new) {
        mesh.rest_uv.push_back(uv);
        first_place.push_back(place);
        extent = std::max(extent, uv.cwiseAbs().maxCoeff());
      } else if (!same_texture_coordinates(mesh.rest_uv[id], uv,
                                           std::max(extent, uv.cwiseAbs().maxCoeff()))) {
        fail(place + ": the vertex at " + format_short(position) + " has texture coordinates " +
             format_short(uv) + " here but " + format_short(mesh.rest_uv[id]) + " at " +
             first_place[id] + "; " + kSeamAdvice);
      }
    }
  }

  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* source = scene->mMeshes[m];
    for (unsigned f = 0; f < source->mNumFaces; ++f) {
      const aiFace& face = source->mFaces[f];
      // Polygons are split into a fan from their first corner, as the OBJ reader does
      // (assimp's own triangulation aborts on some malformed PLY files); points and lines
      // are skipped.
      for (unsigned fan = 1; fan + 1 < face.mNumIndices; ++fan) {
        const Tri tri(id_of[m][face.mIndices[0]], id_of[m][face.mIndices[fan]],
                      id_of[m][face.mIndices[fan + 1]]);
        mesh.triangles.push_back(tri);
        data.triangle_places.push_back(place_of(m, f));
      }
    }
  }
  return data;
}

}  // namespace tissu
