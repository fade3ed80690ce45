// Geometry that keeps the ground and the background cheap on a software rasterizer,
// where every pass over a pixel costs (four times over with MSAA):
//  - the ground square split so that only the part near its edge works out its fade,
//  - where the key light's shadow can fall on it, and
//  - the background drawn only outside the ground's outline on screen.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <vector>

#include "render/gl/mesh_buffer.h"
#include "render/scene_bounds.h"

namespace tissu {

// Rectangle [min, max] in the ground plane's (x, y).
struct GroundRect {
  glm::dvec2 min, max;
};

// Where on the horizontal plane z = height the shadow of anything inside the convex hull
// of `points` (a cloth's vertices, an obstacle's box corners) can fall for light travelling
// along `direction`, grown by `margin` (m). Empty when the light does not come from above
// the plane.
std::optional<GroundRect> shadow_footprint(const std::vector<Vec3>& points, const Vec3& direction,
                                           double height, double margin);

// The square `square` (the ground, world coordinates, normal +z) cut into the cells of a
// regular grid of `divisions` x `divisions`, with shared corners (no T-junctions, so no
// cracks between the parts), counter-clockwise seen from +z. Each cell goes to the part
// whose shader it needs: entirely within `opaque_radius` of `fade_centre` or not (where
// the ground is sure not to fade, its colour is the flat lit colour: no fade or background
// blend to work out per pixel).
struct SplitGround {
  IndexedMesh fading;  // reaching past the opaque disc
  IndexedMesh opaque;  // inside the opaque disc
};
SplitGround split_ground(const GroundRect& square, double height, const glm::dvec2& fade_centre,
                         double opaque_radius, int divisions);

// The fading part alone, for when the opaque disc is not drawn (cleared to its colour
// beforehand): the square less a polygon of at least `sides` sides inscribed in the disc,
// as a ring of quads from the polygon out to the square along rays from `fade_centre`
// (through the square's corners too). Far fewer pixels run the fading shader than with
// the grid's cells along the disc's edge, for a few dozen triangles. Nothing
// (std::nullopt) when the disc is not inside the square.
std::optional<IndexedMesh> ground_ring(const GroundRect& square, double height,
                                       const glm::dvec2& fade_centre, double opaque_radius, int sides);

// Whether all of `rect` lies within `radius` of `centre`.
bool rect_within_disc(const GroundRect& rect, const glm::dvec2& centre, double radius);

// Triangles (normalized device x, y) covering the whole viewport except the inside of
// the convex polygon `corners` (clip-space positions, before the perspective division),
// whose outline is pulled in by `inset_pixels` so that the two overlap a little.
std::vector<glm::vec2> outside_of_polygon(const std::vector<glm::vec4>& corners, int width,
                                          int height, double inset_pixels);

}  // namespace tissu
