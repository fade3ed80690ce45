// The resolved scene: a scene document after its --set overrides, with every material
// preset written out as its numbers and every file path made absolute, so the document
// alone runs the same scene from any directory (the run report records it).
#pragma once

#include "scene/scene.h"

namespace tissu {

// `doc` is the scene document after overrides and `scene` what parse_scene made of it.
// Units are those of the scene format (SI, docs/scenes.md).
Json resolved_scene(const Json& doc, const Scene& scene);

// The scene-file form of `material` (as a custom material object).
Json material_json(const Material& material);

}  // namespace tissu
