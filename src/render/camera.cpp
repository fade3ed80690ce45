#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include "render/scene_bounds.h"

namespace tissu {

namespace {

constexpr double kMargin = 1.12;  // framing leaves ~6% of the view free on each side

// From the target towards the eye: in front (-y), to the right (+x) and above.
const Vec3 kDefaultViewBack = Vec3(0.5, -1.0, 0.55).normalized();

// A unit vector perpendicular to `forward`, as close to `up` as possible.
Vec3 screen_up(const Vec3& forward, const Vec3& up) {
  Vec3 u = up - up.dot(forward) * forward;
  if (u.norm() < 1e-6) {  // up parallel to the view: fall back to any perpendicular
    u = forward.unitOrthogonal();
  }
  return u.normalized();
}

// Distance from `target` along `back` at which every point fits in the view.
double fitting_distance(const std::vector<Vec3>& points, const Vec3& target, const Vec3& back,
                        const Vec3& up, double tan_half_v, double tan_half_h) {
  const Vec3 forward = -back;
  const Vec3 u = screen_up(forward, up);
  const Vec3 right = forward.cross(u);
  double distance = 0.0;
  for (const Vec3& p : points) {
    const Vec3 q = p - target;
    // Camera at target + d*back sees q at depth d - q.back; it must hold |x| <= depth * tan.
    const double toward_eye = q.dot(back);
    distance = std::max(distance, toward_eye + std::abs(q.dot(right)) * kMargin / tan_half_h);
    distance = std::max(distance, toward_eye + std::abs(q.dot(u)) * kMargin / tan_half_v);
    distance = std::max(distance, toward_eye + 1e-3);
  }
  return distance;
}

}  // namespace

Camera auto_camera(const FrameContent& content, double aspect, const CameraSettings& settings,
                   std::optional<double> ground_height) {
  return auto_camera(content_bounds(content), content.obstacles, aspect, settings, ground_height);
}

Camera auto_camera(const Box3& shown, const std::vector<ObstacleShape>& obstacles, double aspect,
                   const CameraSettings& settings, std::optional<double> ground_height) {
  Box3 box = shown;
  if (box.isEmpty()) box = Box3(Vec3::Constant(-0.5), Vec3::Constant(0.5));
  // Stretch the box down to planes and ground below it, where cloth will land.
  std::vector<Vec3> points = box_corners(box);
  for (const ObstacleShape& o : obstacles) {
    if (o.kind != ObstacleShape::Kind::Plane) continue;
    const Vec3 n = o.axis.normalized();
    for (const Vec3& c : box_corners(box)) {
      const double above = (c - o.center).dot(n);
      if (above > 0) points.push_back(c - above * n);
    }
  }
  if (ground_height && *ground_height < box.max().z()) {
    for (const Vec3& c : box_corners(box)) points.emplace_back(c.x(), c.y(), *ground_height);
  }
  Box3 framed;
  for (const Vec3& p : points) framed.extend(p);

  Camera camera;
  camera.up = settings.up;
  camera.fov_deg = settings.fov_deg;
  camera.target = settings.target.value_or(framed.center());
  const double tan_half_v = std::tan(camera.fov_deg * kPi / 360.0);
  const double tan_half_h = tan_half_v * aspect;
  if (settings.eye) {
    camera.eye = *settings.eye;
  } else {
    Vec3 back = kDefaultViewBack;
    if (back.cross(camera.up.normalized()).norm() < 1e-3) back = camera.up.unitOrthogonal();
    camera.eye = camera.target + back * fitting_distance(points, camera.target, back, camera.up,
                                                         tan_half_v, tan_half_h);
  }
  if ((camera.eye - camera.target).norm() < 1e-9) camera.eye = camera.target + kDefaultViewBack;
  return camera;
}

}  // namespace tissu
