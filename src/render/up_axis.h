// A scene may take any direction as up (minus its gravity, or render.up); the renderer
// draws with +z up. These turn what a scene gives, in its own coordinates, into the
// renderer's: one rotation, so distances, angles and "height above the ground" are kept.
#pragma once

#include "core/types.h"
#include "render/camera.h"
#include "render/frame_content.h"
#include "render/render_settings.h"

namespace tissu {

// The rotation R with R * up / |up| = +z (the shortest one; the identity for up = +z).
Mat3 rotation_up_to_z(const Vec3& up);
bool is_identity(const Mat3& rotation);

ObstacleShape turned(const ObstacleShape& shape, const Mat3& rotation);
// Positions and obstacles turned; triangles, uv and text kept. `out` is reused.
void turn_content(const FrameContent& content, const Mat3& rotation, FrameContent& out);
Camera turned(const Camera& camera, const Mat3& rotation);
// Camera, lights and up of `settings`, turned; with up = +z the result draws as `settings`.
RenderSettings turned(const RenderSettings& settings, const Mat3& rotation);

}  // namespace tissu
