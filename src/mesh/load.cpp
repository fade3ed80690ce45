#include "mesh/load.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/mesh_readers.h"
#include "mesh/validate.h"

namespace tissu {
namespace {

bool has_obj_extension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".obj";
}

void require_regular_file(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) {
    throw InputError(path + ": cannot open: " + std::strerror(errno));
  }
  if (!S_ISREG(info.st_mode)) throw InputError(path + ": cannot open: not a regular file");
}

}  // namespace

void set_rest_uv_from_plane(TriMesh& mesh, const std::string& source_name) {
  auto fail = [&](const std::string& problem) { throw InputError(source_name + ": " + problem); };
  if (mesh.triangles.empty()) fail("contains no triangles");
  const std::string advice =
      ": give the file texture coordinates (in m, or scaled by uv_scale) or a flat rest shape";

  Vec3 normal = Vec3::Zero();
  std::vector<char> used(mesh.positions.size(), 0);
  for (const Tri& t : mesh.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= static_cast<int>(mesh.positions.size())) {
      fail("a triangle's vertex id is out of range");
    }
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    normal += (b - a).cross(c - a);
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = -lo, centre = Vec3::Zero();
  int count = 0;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!used[v]) continue;
    lo = lo.cwiseMin(mesh.positions[v]);
    hi = hi.cwiseMax(mesh.positions[v]);
    centre += mesh.positions[v];
    ++count;
  }
  centre /= count;
  const double diagonal = (hi - lo).norm();
  if (!(normal.norm() > 1e-12 * diagonal * diagonal)) {
    fail("no texture coordinates and no plane to project onto (the triangles' areas are zero or "
         "cancel out)" + advice);
  }
  normal.normalize();
  const double tolerance = kFlatTolerance * diagonal;
  size_t farthest = 0;
  double farthest_distance = -1;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const double distance = std::abs((mesh.positions[v] - centre).dot(normal));
    if (used[v] && distance > farthest_distance) {
      farthest = v;
      farthest_distance = distance;
    }
  }
  if (farthest_distance > tolerance) {
    fail("no texture coordinates and not flat: vertex id " + std::to_string(farthest) + " is " +
         format_short(farthest_distance) + " m from the mean plane (tolerance " +
         format_short(tolerance) + " m)" + advice);
  }

  Vec3 u = Vec3::UnitX() - normal.x() * normal;  // x projected onto the plane
  if (u.norm() < 0.1) u = Vec3::UnitY() - normal.y() * normal;
  u.normalize();
  const Vec3 v = normal.cross(u);
  mesh.rest_uv.resize(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    mesh.rest_uv[i] = Vec2(mesh.positions[i].dot(u), mesh.positions[i].dot(v));
  }
  mesh.uv_from_file = false;
}

TriMesh load_mesh(const std::string& path, double uv_scale) {
  if (!(std::isfinite(uv_scale) && uv_scale > 0)) {
    throw InputError(path + ": uv_scale must be positive, got " + format_short(uv_scale));
  }
  require_regular_file(path);
  MeshFileData data = has_obj_extension(path) ? read_obj(path) : read_with_assimp(path);
  TriMesh& mesh = data.mesh;
  if (mesh.triangles.empty()) throw InputError(path + ": contains no triangles");
  if (mesh.uv_from_file) {
    for (Vec2& uv : mesh.rest_uv) uv *= uv_scale;
  } else {
    set_rest_uv_from_plane(mesh, path);
  }
  validate_mesh(mesh, path, std::move(data.triangle_places));
  return std::move(data.mesh);
}

SurfaceFile load_surface(const std::string& path) {
  require_regular_file(path);
  MeshFileData data = has_obj_extension(path) ? read_obj(path, false)
                                              : read_with_assimp(path, false);
  if (data.mesh.triangles.empty()) throw InputError(path + ": contains no triangles");
  return {std::move(data.mesh.positions), std::move(data.mesh.triangles),
          std::move(data.triangle_places)};
}

}  // namespace tissu
