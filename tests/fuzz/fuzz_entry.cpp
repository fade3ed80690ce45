#include "fuzz_entry.h"

#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "mesh/load.h"
#include "scene/scene.h"

namespace tissu::fuzz {
namespace {

namespace fs = std::filesystem;

// A private directory for the files the entries write, removed when the process exits.
class Scratch {
 public:
  Scratch() {
    std::string pattern = (fs::temp_directory_path() / "tissu-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("fuzz: mkdtemp failed");
    dir_ = pattern;
    // A valid 2 x 2 square with texture coordinates, for scenes that name a mesh file.
    write("cloth.obj",
          "v 0 0 0\nv 0.5 0 0\nv 1 0 0\nv 0 0.5 0\nv 0.5 0.5 0\nv 1 0.5 0\n"
          "v 0 1 0\nv 0.5 1 0\nv 1 1 0\n"
          "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 0.5\nvt 0.5 0.5\nvt 1 0.5\nvt 0 1\nvt 0.5 1\nvt 1 1\n"
          "f 1/1 2/2 5/5\nf 1/1 5/5 4/4\nf 2/2 3/3 6/6\nf 2/2 6/6 5/5\n"
          "f 4/4 5/5 8/8\nf 4/4 8/8 7/7\nf 5/5 6/6 9/9\nf 5/5 9/9 8/8\n");
  }
  ~Scratch() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::string write(const std::string& name, std::string_view bytes) const {
    const std::string path = (dir_ / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("fuzz: cannot write " + path);
    return path;
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

const Scratch& scratch() {
  static const Scratch instance;
  return instance;
}

[[noreturn]] void broken(const std::string& what) { throw FuzzInvariantError("fuzz: " + what); }

bool finite(const Vec3List& list) {
  for (const Vec3& v : list) {
    if (!v.allFinite()) return false;
  }
  return true;
}

void check_simulation(const Simulation& sim) {
  const Model& m = sim.model;
  const State& s = sim.state;
  const size_t n = m.rest_uv.size();
  if (n == 0 || m.triangles.empty()) broken("built a simulation without vertices or triangles");
  if (s.x.size() != n || s.v.size() != n || m.mass.size() != n || m.pinned.size() != n) {
    broken("per-vertex arrays of different lengths");
  }
  if (!finite(s.x)) broken("built a simulation with a non-finite position");
  if (!finite(s.v)) broken("built a simulation with a non-finite velocity");
  for (size_t i = 0; i < n; ++i) {
    if (!m.rest_uv[i].allFinite()) broken("non-finite rest coordinates");
    if (!(std::isfinite(m.mass[i]) && m.mass[i] >= 0)) broken("non-finite or negative mass");
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const TriangleRest& r = m.rest[t];
    if (!(std::isfinite(r.area) && r.area > 0)) broken("rest area not positive and finite");
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(r.ru[k]) || !std::isfinite(r.rv[k])) broken("non-finite rest factors");
    }
  }
}

void check_mesh(const TriMesh& mesh) {
  if (mesh.triangles.empty()) broken("loaded a mesh without triangles");
  if (mesh.positions.size() != mesh.rest_uv.size()) broken("positions and rest_uv differ");
  if (!finite(mesh.positions)) broken("loaded a non-finite position");
  for (const Vec2& uv : mesh.rest_uv) {
    if (!uv.allFinite()) broken("loaded non-finite rest coordinates");
  }
  const long long n = static_cast<long long>(mesh.positions.size());
  for (const Tri& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= n) broken("loaded a vertex id out of range");
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) broken("loaded a degenerate triangle");
  }
}

bool small_enough_to_build(const Scene& scene) {
  if (scene.mesh.kind == MeshSpec::Kind::File) {
    // Only files the fuzzer controls: never wander the file system.
    return fs::path(scene.mesh.file).parent_path() == scratch().dir();
  }
  return scene.mesh.triangles <= kMaxFuzzTriangles;
}

}  // namespace

void scene_input(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  constexpr std::string_view kSet = "//--set ";
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    if (line.substr(0, kSet.size()) == kSet) overrides.emplace_back(line.substr(kSet.size()));
    start = end + 1;
  }
  const std::string file = scratch().write("scene.json", text);
  const Scene scene = load_scene(file, overrides);
  if (!small_enough_to_build(scene)) return;
  check_simulation(build_simulation(scene));
}

void mesh_input(const uint8_t* data, size_t size) {
  static const char* const kFormats[] = {"obj", "ply", "stl", "off"};
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::string format;
  std::string_view file = bytes;
  const std::string_view first_line = bytes.substr(0, bytes.find('\n'));
  for (const char* f : kFormats) {
    if (first_line == f && first_line.size() < bytes.size()) {
      format = f;
      file = bytes.substr(first_line.size() + 1);
    }
  }
  if (format.empty()) format = size > 0 ? kFormats[data[0] % 4] : "obj";
  const std::string path = scratch().write("mesh." + format, file);
  check_mesh(load_mesh(path, 1.0));
}

}  // namespace tissu::fuzz
