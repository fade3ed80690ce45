#include "render/up_axis.h"

#include <Eigen/Geometry>

namespace tissu {

Mat3 rotation_up_to_z(const Vec3& up) {
  return Eigen::Quaterniond::FromTwoVectors(up.normalized(), Vec3::UnitZ()).toRotationMatrix();
}

bool is_identity(const Mat3& rotation) { return (rotation - Mat3::Identity()).norm() < 1e-14; }

ObstacleShape turned(const ObstacleShape& shape, const Mat3& rotation) {
  ObstacleShape out = shape;
  out.center = rotation * shape.center;
  out.axis = rotation * shape.axis;
  // A mesh is drawn at center + rotation * (v - pivot): turning it turns its pose.
  out.rotation = rotation * shape.rotation;
  return out;
}

void turn_content(const FrameContent& content, const Mat3& rotation, FrameContent& out) {
  out.positions.resize(content.positions.size());
  for (size_t i = 0; i < content.positions.size(); ++i) {
    out.positions[i] = rotation * content.positions[i];
  }
  if (out.triangles != content.triangles) out.triangles = content.triangles;
  if (out.rest_uv != content.rest_uv) out.rest_uv = content.rest_uv;
  out.obstacles.clear();
  for (const ObstacleShape& o : content.obstacles) out.obstacles.push_back(turned(o, rotation));
  out.overlay_lines = content.overlay_lines;
}

Camera turned(const Camera& camera, const Mat3& rotation) {
  Camera out = camera;
  out.eye = rotation * camera.eye;
  out.target = rotation * camera.target;
  out.up = rotation * camera.up;
  return out;
}

RenderSettings turned(const RenderSettings& settings, const Mat3& rotation) {
  RenderSettings out = settings;
  out.up = rotation * settings.up;
  if (settings.camera.eye) out.camera.eye = rotation * *settings.camera.eye;
  if (settings.camera.target) out.camera.target = rotation * *settings.camera.target;
  out.camera.up = rotation * settings.camera.up;
  for (Light& light : out.lights) light.direction = rotation * light.direction;
  return out;
}

}  // namespace tissu
