// Physics obstacles as the renderer draws them, for `tissu render` (RenderSink) and the
// figure panels. Lives here because this is the lowest library that sees both physics
// and the renderer (the renderer does not depend on physics).
#pragma once

#include "physics/obstacle.h"
#include "render/frame_content.h"

namespace tissu {

// `ob` at time t, drawn `inset` m inside its surface (radius and half length shrink by
// it; cloth resting on the obstacle would otherwise be cut by its tessellation). Planes
// are drawn 2 mm below their surface, meshes as they are (no tessellation to hide).
ObstacleShape drawn_obstacle(const Obstacle& ob, double t, double inset);

}  // namespace tissu
