// A scene's "render" block read into the renderer's plain settings (docs/rendering.md
// lists every key). The renderer itself takes RenderSettings and knows no JSON.
#pragma once

#include <optional>

#include "core/types.h"
#include "render/render_settings.h"
#include "scene/json_reader.h"

namespace tissu {

// Reads a "render" block (every key optional). `scene_up` is the scene's up when the block
// gives none (minus gravity). Camera, lights and ground given in the block are in the
// scene's coordinates; the default lights and camera up follow `up`. Throws InputError
// "<json path>: <problem>" for bad values and unknown keys (finish() is called).
RenderSettings parse_render_settings(JsonReader& render, const Vec3& scene_up = Vec3::UnitZ());

// Up for a scene whose gravity is `gravity` (m/s^2): -gravity, or +z without gravity.
Vec3 up_from_gravity(const std::optional<Vec3>& gravity);

}  // namespace tissu
