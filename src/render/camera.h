// The camera of a run and its automatic framing. World z is up.
#pragma once

#include <optional>

#include "core/types.h"

namespace tissu {

struct FrameContent;

struct Camera {
  Vec3 eye = Vec3(0, -3, 1.5);      // position (m)
  Vec3 target = Vec3::Zero();       // point looked at (m)
  Vec3 up = Vec3::UnitZ();          // roughly up on screen
  double fov_deg = 40.0;            // vertical field of view (degrees)
};

// The scene's camera block: eye and/or target may be left to automatic framing.
struct CameraSettings {
  std::optional<Vec3> eye;
  std::optional<Vec3> target;
  Vec3 up = Vec3::UnitZ();
  double fov_deg = 40.0;
  bool fixed() const { return eye.has_value() && target.has_value(); }
};

// A camera that frames the bounding box of the cloth and the sphere/cylinder
// obstacles of `content`, seen from the front, right and above. Plane obstacles and
// the ground (when given) stretch the box down onto them, so falling cloth stays in
// view. Eye or target given in `settings` are kept. Compute it once per run (from the
// first frame) so the view does not jump. `aspect` = width / height.
Camera auto_camera(const FrameContent& content, double aspect, const CameraSettings& settings = {},
                   std::optional<double> ground_height = std::nullopt);

}  // namespace tissu
