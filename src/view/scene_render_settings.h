// A scene's render block as the renderer takes it: the one reading of it, for `tissu render`,
// the figure panels and the paper's timing.
#pragma once

#include "render/render_settings.h"
#include "scene/scene.h"

namespace tissu {

// The scene's render block, validated (defaults when the scene has none); up defaults to
// minus the scene's gravity. Errors name the scene file, or the --set override that set
// the value.
RenderSettings render_settings_of(const Scene& scene);

// The same for a still at `width` x `height`: without caption and corner text.
RenderSettings still_render_settings(const Scene& scene, int width, int height);

}  // namespace tissu
