// Axis-aligned bounds of what a frame shows: cloth vertices and the finite
// obstacles (spheres, cylinders). Planes are unbounded and not included.
#pragma once

#include <Eigen/Geometry>

#include "render/frame_content.h"

namespace tissu {

using Box3 = Eigen::AlignedBox3d;

Box3 content_bounds(const FrameContent& content);
// The same for cloth `positions` and `obstacles` (non-finite positions are left out).
Box3 shown_bounds(const Vec3List& positions, const std::vector<ObstacleShape>& obstacles);

// The eight corners of a non-empty box.
std::vector<Vec3> box_corners(const Box3& box);

}  // namespace tissu
