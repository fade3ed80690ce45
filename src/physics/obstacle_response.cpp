#include "physics/obstacle_response.h"

#include <algorithm>
#include <cmath>

#include "physics/force_plan.h"
#include "physics/obstacle_simd.h"

namespace tissu {

namespace {

// Signed distance (m) from p to a placed obstacle's surface and the outward normal, or
// +infinity when p is beyond a sphere's contact distance (the common case, decided
// without a square root).
double distance_if_near(const PlacedObstacle& placed, const Vec3& p, Vec3* normal) {
  const Obstacle& ob = *placed.obstacle;
  const double reach = ob.radius + ob.thickness;
  if (ob.kind == ObstacleKind::Sphere && (p - placed.center).squaredNorm() >= reach * reach) {
    return INFINITY;
  }
  return ob.signed_distance_from(p, placed.center, normal, placed.rotation, ob.thickness);
}

}  // namespace

double collide_vertex(const std::vector<PlacedObstacle>& obstacles, CollisionResponse response,
                      Vec3& x, Vec3& v) {
  constexpr int kPasses = 4;
  double work = 0.0;  // m^2/s^2
  for (int pass = 0; pass < kPasses; ++pass) {
    bool moved = false;
    for (const PlacedObstacle& placed : obstacles) {
      Vec3 n;
      const double shortfall = placed.obstacle->thickness - distance_if_near(placed, x, &n);
      if (!(shortfall > response.tolerance)) continue;
      moved = true;
      x += shortfall * n;
      const Vec3 surface_velocity =
          placed.velocity + placed.angular_velocity.cross(x - placed.center);
      const Vec3 relative = v - surface_velocity;
      const double vn = relative.dot(n);
      if (vn >= 0.0) continue;
      const Vec3 sliding = relative - vn * n;
      Vec3 tangential = sliding;
      if (response.friction) {
        const double vt = sliding.norm();
        const double slow = placed.obstacle->friction * (-vn);
        tangential = (vt <= slow) ? Vec3::Zero() : Vec3(sliding * (1.0 - slow / vt));
        if (response.position_weight > 0.0) {
          // Along the surface, then back out of it where it curves (or another face is near).
          x += response.position_weight * (tangential - sliding);
          Vec3 m;
          const double again = placed.obstacle->thickness - distance_if_near(placed, x, &m);
          if (again > 0.0) x += again * m;
        }
      }
      const Vec3 changed = surface_velocity + tangential;
      work += (changed - v).dot(surface_velocity);
      v = changed;
    }
    if (!moved) break;
  }
  return work;
}

double collide_block(const std::vector<PlacedObstacle>& obstacles, CollisionResponse response,
                     const std::vector<uint8_t>& pinned, const std::vector<double>& mass,
                     int first, int end, Vec3List& x, Vec3List& v) {
  int near[ForcePlan::kVerticesPerBlock];
  double work = 0.0;  // J
  for (int begin = first; begin < end; begin += ForcePlan::kVerticesPerBlock) {
    const int stop = std::min(end, begin + ForcePlan::kVerticesPerBlock);
    const int count = select_near_obstacles(obstacles, x, begin, stop, near);
    for (int k = 0; k < count; ++k) {
      const int i = near[k];
      if (!pinned[i]) work += mass[i] * collide_vertex(obstacles, response, x[i], v[i]);
    }
  }
  return work;
}

}  // namespace tissu
