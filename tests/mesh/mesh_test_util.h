// Helpers shared by the mesh tests: a temporary directory, small files, caught messages.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/input_error_of.h"
#include "core/error.h"

namespace tissu::test {

// A fresh directory under the system's temporary directory, removed with its contents.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "tissu-mesh-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  // Writes `text` to `name` and returns the full path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream out(file(name), std::ios::binary);
    out << text;
    return file(name);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A unit square as an ASCII PLY of 2 triangles with texture coordinates (s, t) = 2 (x, y)
// and vertex 0 lifted to z = 0.5 (read by assimp).
inline constexpr char kSquarePly[] =
    "ply\nformat ascii 1.0\n"
    "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float s\nproperty float t\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0.5 0 0\n1 0 0 2 0\n1 1 0 2 2\n0 1 0 0 2\n"
    "3 0 1 2\n3 0 2 3\n";

}  // namespace tissu::test
