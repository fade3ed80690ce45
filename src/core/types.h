// Basic vector types and constants shared by every module. Units are SI throughout.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace tissu {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Tri = Eigen::Vector3i;  // three vertex ids of a triangle

using Vec3List = std::vector<Vec3>;
using Vec2List = std::vector<Vec2>;
using TriList = std::vector<Tri>;

constexpr double kPi = 3.14159265358979323846;

}  // namespace tissu
