// Writing a mesh as a Wavefront OBJ file that load_mesh reads back unchanged.
#pragma once

#include <string>

#include "core/types.h"

namespace tissu {

// Writes `v` lines (positions, m), `vt` lines (rest u, v, m; none when rest_uv is empty) and
// `f a/a b/b c/c` lines (1-based), in the order given. Numbers are written in the shortest
// form that reads back to the same double. Atomic: the file is written under its temporary
// name and renamed over `path` only when complete (core/partial_file.h), so `path` is
// either untouched or whole. Failures raise OutputError naming the file and the system's
// reason, and leave no temporary file.
// Mismatched sizes or vertex ids out of range raise std::invalid_argument.
void write_obj(const std::string& path, const Vec3List& positions, const Vec2List& rest_uv,
               const TriList& triangles);

}  // namespace tissu
