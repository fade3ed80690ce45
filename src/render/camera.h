// The camera of a run and its automatic framing, in the renderer's coordinates: z up
// (render/up_axis.h turns a scene's own up into z).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "core/types.h"

namespace tissu {

struct FrameContent;
struct ObstacleShape;

struct Camera {
  Vec3 eye = Vec3(0, -3, 1.5);      // position (m)
  Vec3 target = Vec3::Zero();       // point looked at (m)
  Vec3 up = Vec3::UnitZ();          // roughly up on screen
  double fov_deg = 40.0;            // vertical field of view (degrees)
};

// What the automatic camera frames: everything the run shows (frames are held until the
// run ends, 24 bytes per cloth vertex per frame), or the first frame only.
enum class Framing { Run, First };

// The scene's camera block: eye and/or target may be left to automatic framing.
struct CameraSettings {
  std::optional<Vec3> eye;
  std::optional<Vec3> target;
  Vec3 up = Vec3::UnitZ();
  double fov_deg = 40.0;
  Framing framing = Framing::Run;
  bool fixed() const { return eye.has_value() && target.has_value(); }
};

// A camera (z up) that frames the box `shown` (cloth and finite obstacles, over one frame
// or a whole run), seen from the front, right and above. The plane obstacles among
// `obstacles` and the ground (when given) stretch the box down onto them, so falling
// cloth stays in view. Eye or target given in `settings` are kept. `aspect` = width / height.
Camera auto_camera(const Eigen::AlignedBox3d& shown, const std::vector<ObstacleShape>& obstacles,
                   double aspect, const CameraSettings& settings = {},
                   std::optional<double> ground_height = std::nullopt);
// The camera framing one frame's content.
Camera auto_camera(const FrameContent& content, double aspect, const CameraSettings& settings = {},
                   std::optional<double> ground_height = std::nullopt);

}  // namespace tissu
