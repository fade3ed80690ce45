// Physics obstacles as the renderer draws them, for `tissu render` (RenderSink) and the
// figure panels. Lives here because this is the lowest library that sees both physics
// and the renderer (the renderer does not depend on physics).
#pragma once

#include "physics/obstacle.h"
#include "render/frame_content.h"

namespace tissu {

// `ob` at time t as the surface cloth rests on, its thickness out from its own surface,
// drawn `inset` m inside that (radius and half length shrink by it; cloth resting on the
// obstacle would otherwise be cut by its tessellation). Planes are drawn 2 mm below that
// surface, meshes as their file gives them (no tessellation to hide; their thickness, a
// few millimetres, is not drawn).
ObstacleShape drawn_obstacle(const Obstacle& ob, double t, double inset);

}  // namespace tissu
