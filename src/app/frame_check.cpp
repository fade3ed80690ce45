#include "app/frame_check.h"

#include "collision/closed_surface.h"
#include "collision/crossings.h"

namespace tissu {

FrameCheck check_frame(const Model& model, const State& state) {
  FrameCheck check;
  check.step = state.step;
  check.time = state.t;
  const CrossingReport self = self_crossings(state.x, model.triangles);
  check.cloth_pairs = self.count;
  if (self.any()) {
    check.first = "cloth triangles " + std::to_string(self.pairs[0].first) + " and " +
                  std::to_string(self.pairs[0].second) + " cross";
  }
  for (size_t o = 0; o < model.obstacles.size(); ++o) {
    const Obstacle& ob = model.obstacles[o];
    if (ob.kind != ObstacleKind::Mesh) continue;
    Vec3List placed;
    placed.reserve(ob.surface->vertices().size());
    for (const Vec3& p : ob.surface->vertices()) placed.push_back(ob.carried(p, state.t));
    const CrossingReport cross =
        crossings_between(state.x, model.triangles, placed, ob.surface->triangles());
    check.obstacle_pairs += cross.count;
    if (cross.any() && check.first.empty()) {
      check.first = "cloth triangle " + std::to_string(cross.pairs[0].first) +
                    " crosses triangle " + std::to_string(cross.pairs[0].second) +
                    " of obstacle " + std::to_string(o);
    }
  }
  return check;
}

CheckSummary summarize_checks(const std::vector<FrameCheck>& checks) {
  CheckSummary summary;
  for (const FrameCheck& c : checks) {
    if (c.clean()) continue;
    ++summary.frames_with_crossings;
    if (c.obstacle_pairs > 0) ++summary.frames_with_obstacle_crossings;
    if (!summary.first) summary.first = &c;
  }
  return summary;
}

}  // namespace tissu
