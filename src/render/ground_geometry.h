// Geometry that keeps the ground and the background cheap on a software rasterizer,
// where every pass over a pixel costs (four times over with MSAA):
//  - the ground square split so that only the part where the key light's shadow can fall
//    runs the shadow-map look-up, and
//  - the background drawn only outside the ground's outline on screen.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <vector>

#include "render/mesh_buffer.h"
#include "render/scene_bounds.h"

namespace tissu {

// Rectangle [min, max] in the ground plane's (x, y).
struct GroundRect {
  glm::dvec2 min, max;
};

// Where on the horizontal plane z = height the shadow of anything inside `casters` can
// fall for light travelling along `direction`, grown by `margin` (m). Empty when the light
// does not come from above the plane.
std::optional<GroundRect> shadow_footprint(const Box3& casters, const Vec3& direction,
                                           double height, double margin);

// The square `square` (the ground, world coordinates, normal +z) split along the lines of
// `inner` (clamped to the square) into its middle cell and the eight cells around it
// (3 x 3 cells, shared corners, counter-clockwise seen from +z).
struct SplitGround {
  IndexedMesh inner;  // empty when `inner` misses the square
  IndexedMesh outer;
};
SplitGround split_ground(const GroundRect& square, double height, const GroundRect& inner);
IndexedMesh ground_mesh(const GroundRect& square, double height);  // one cell

// Triangles (normalized device x, y) covering the whole viewport except the inside of
// the convex polygon `corners` (clip-space positions, before the perspective division),
// whose outline is pulled in by `inset_pixels` so that the two overlap a little.
std::vector<glm::vec2> outside_of_polygon(const std::vector<glm::vec4>& corners, int width,
                                          int height, double inset_pixels);

}  // namespace tissu
