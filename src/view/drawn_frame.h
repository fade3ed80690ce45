// The simulation as the renderer draws it: the one conversion of a Model and a State into
// FrameContent, used by `tissu render` (RenderSink), the figure panels and the paper's
// timing. Lives in view/, the lowest library that sees both physics and the renderer (the
// renderer does not depend on physics).
#pragma once

#include <vector>

#include "physics/model.h"
#include "render/frame_content.h"

namespace tissu {

// Mean length of the cloth's edges at positions `x`, m (0 without triangles).
double mean_edge_length(const Model& model, const Vec3List& x);

// How far inside its surface an obstacle of `radius` m is drawn under cloth of edges
// `edge_length` m long, m. Cloth resting on an obstacle has its vertices on the surface and
// its flat triangles inside it by the sagitta L^2 / (8 R) of an edge: drawn at full size the
// obstacle would show through. The inset is twice that sagitta plus 0.5 % of the radius,
// at most 20 % of it.
double obstacle_inset(double radius, double edge_length);

// `ob` at time t as the surface cloth rests on, its thickness out from its own surface,
// drawn `inset` m inside that (radius and half length shrink by it). Planes are drawn 2 mm
// below that surface, meshes as their file gives them (no tessellation to hide; their
// thickness, a few millimetres, is not drawn).
ObstacleShape drawn_obstacle(const Obstacle& ob, double t, double inset);

// Every obstacle of `model` at time t, inset for cloth edges of `edge_length` m.
std::vector<ObstacleShape> drawn_obstacles(const Model& model, double t, double edge_length);

// The cloth at `state` and the obstacles at state.t, inset for cloth edges of
// `edge_length` m (a run's first frame fixes it: mean_edge_length of its positions).
FrameContent drawn_frame(const Model& model, const State& state, double edge_length);

}  // namespace tissu
