// A scene's render block as the renderer takes it, with the scene's own up.
#pragma once

#include "render/render_settings.h"
#include "scene/scene.h"

namespace tissu {

// The scene's render block, validated (defaults when the scene has none); up defaults to
// minus the scene's gravity. Errors name the scene file, or the --set override that set
// the value.
RenderSettings render_settings_of(const Scene& scene);

}  // namespace tissu
