// Entry functions of the fuzz targets, shared by the libFuzzer executables (TISSU_FUZZ=ON,
// clang) and by fuzz_regression_test (any compiler), which replays tests/fuzz/corpus and
// tests/fuzz/regressions through them.
//
// Contract: for any bytes, an entry function returns normally or throws tissu::InputError.
// Anything else (another exception, a crash, undefined behaviour, a leak, a hang) is a bug.
// A broken invariant of a successful result throws FuzzInvariantError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>

namespace tissu::fuzz {

struct FuzzInvariantError : std::logic_error {
  using std::logic_error::logic_error;
};

// The scene reader. The bytes are a scene file; lines starting with "//--set " (JSON
// comments, so the file stays a valid scene) also become `--set` overrides. The bytes are
// written to <scratch>/scene.json and go through load_scene, then build_simulation when the
// scene is small: a generated mesh of at most kMaxFuzzTriangles triangles, or a mesh file
// in the scratch directory (it holds cloth.obj, a valid 2 x 2 square). A built simulation
// must have finite positions, velocities, masses and positive rest areas.
constexpr long long kMaxFuzzTriangles = 3000;
void scene_input(const uint8_t* data, size_t size);

// The mesh loader. When the first line is "obj", "ply", "stl" or "off", it names the format
// and the rest is the file; otherwise the whole input is the file, in the format chosen by
// its first byte. The bytes are written to <scratch>/mesh.<format> and go through
// load_mesh. A loaded mesh must pass the checks load_mesh promises (validate_mesh).
void mesh_input(const uint8_t* data, size_t size);

}  // namespace tissu::fuzz
