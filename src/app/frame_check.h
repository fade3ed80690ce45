// `tissu run --check`: every recorded frame is checked with the exact crossing test
// (collision/crossings.h) for cloth triangles that cross each other and cloth triangles
// that cross a mesh obstacle's triangles (at the frame's time).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "physics/model.h"

namespace tissu {

struct FrameCheck {
  long long step = 0;
  double time = 0.0;              // s
  std::size_t cloth_pairs = 0;    // pairs of cloth triangles that intersect
  std::size_t obstacle_pairs = 0; // (cloth triangle, mesh obstacle triangle) pairs
  std::string first;              // the first pair found, in words ("" when none)
  bool clean() const { return cloth_pairs == 0 && obstacle_pairs == 0; }
};

FrameCheck check_frame(const Model& model, const State& state);

// What the checks of a run found: the frames with crossings, and the first of them.
struct CheckSummary {
  std::size_t frames_with_crossings = 0;
  std::size_t frames_with_obstacle_crossings = 0;  // of those, frames where cloth crosses a mesh
  const FrameCheck* first = nullptr;  // into the checks; nullptr when every frame is clean
};
CheckSummary summarize_checks(const std::vector<FrameCheck>& checks);

}  // namespace tissu
