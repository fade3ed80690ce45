// Replays every file of tests/fuzz/corpus/<target>/ and tests/fuzz/regressions/<target>/
// through the fuzz entry functions (fuzz_entry.h): only InputError may escape. Built with
// the normal compiler; under TISSU_SANITIZE=ON the sanitizers check the same inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "fuzz_entry.h"

// Under TISSU_SANITIZE=ON: assimp leaks a half-built mesh on some malformed files (see
// tests/lsan.supp); third-party code only, never the project's.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

namespace tissu::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs_of(const std::string& target) {
  std::vector<fs::path> files;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(TISSU_FUZZ_DIR) / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_regular_file() && entry.path().filename().string()[0] != '.') {
        files.push_back(entry.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Runs every input; returns how many raised InputError.
size_t replay(const std::string& target,
              const std::function<void(const uint8_t*, size_t)>& entry) {
  const std::vector<fs::path> files = inputs_of(target);
  EXPECT_GE(files.size(), 5u) << "the " << target << " corpus is missing";
  size_t rejected = 0;
  std::streambuf* saved = std::cerr.rdbuf(nullptr);  // mesh warnings
  for (const fs::path& file : files) {
    const std::string bytes = bytes_of(file);
    try {
      entry(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    } catch (const InputError&) {
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << file.string() << ": escaped as " << typeid(e).name() << ": " << e.what();
    } catch (...) {
      ADD_FAILURE() << file.string() << ": escaped as a non-standard exception";
    }
  }
  std::cerr.rdbuf(saved);
  std::cout << target << ": " << files.size() << " inputs, " << rejected
            << " rejected with InputError\n";
  return rejected;
}

TEST(FuzzRegression, SceneInputsRaiseOnlyInputError) {
  const size_t rejected = replay("scene", scene_input);
  EXPECT_GT(rejected, 0u) << "the regressions hold bad scenes";
}

TEST(FuzzRegression, MeshInputsRaiseOnlyInputError) {
  const size_t rejected = replay("mesh", mesh_input);
  EXPECT_GT(rejected, 0u) << "the regressions hold bad meshes";
}

// The valid seeds stay valid: a seed named valid_* loads without error.
TEST(FuzzRegression, ValidSeedsLoad) {
  for (const std::string target : {"scene", "mesh"}) {
    for (const fs::path& file : inputs_of(target)) {
      if (file.filename().string().rfind("valid_", 0) != 0) continue;
      const std::string bytes = bytes_of(file);
      const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
      std::streambuf* saved = std::cerr.rdbuf(nullptr);
      try {
        target == "scene" ? scene_input(data, bytes.size()) : mesh_input(data, bytes.size());
      } catch (const std::exception& e) {
        ADD_FAILURE() << file.string() << ": " << e.what();
      }
      std::cerr.rdbuf(saved);
    }
  }
}

}  // namespace
}  // namespace tissu::fuzz
