#include "render/scene_bounds.h"

#include <cmath>

namespace tissu {

Box3 content_bounds(const FrameContent& content) {
  return shown_bounds(content.positions, content.obstacles);
}

Box3 shown_bounds(const Vec3List& positions, const std::vector<ObstacleShape>& obstacles) {
  Box3 box;  // starts empty
  for (const Vec3& p : positions) {
    if (p.allFinite()) box.extend(p);  // a diverging simulation must not wreck the view
  }
  for (const ObstacleShape& o : obstacles) {
    if (o.kind == ObstacleShape::Kind::Sphere) {
      box.extend(o.center - Vec3::Constant(o.radius));
      box.extend(o.center + Vec3::Constant(o.radius));
    } else if (o.kind == ObstacleShape::Kind::Cylinder) {
      const Vec3 axis = o.axis.normalized();
      // Per coordinate, a disc of radius r normal to `axis` reaches r * sqrt(1 - axis_i^2).
      const Vec3 disc = (Vec3::Ones() - axis.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * o.radius;
      for (double end : {-1.0, 1.0}) {
        const Vec3 c = o.center + end * o.half_length * axis;
        box.extend(c - disc);
        box.extend(c + disc);
      }
    } else if (o.kind == ObstacleShape::Kind::Mesh && !o.mesh_bounds.isEmpty()) {
      for (const Vec3& corner : box_corners(o.mesh_bounds)) {
        box.extend(o.center + o.rotation * (corner - o.pivot));
      }
    }
  }
  return box;
}

std::vector<Vec3> box_corners(const Box3& box) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back(i & 1 ? box.max().x() : box.min().x(),
                         i & 2 ? box.max().y() : box.min().y(),
                         i & 4 ? box.max().z() : box.min().z());
  }
  return corners;
}

}  // namespace tissu
