#include "view/scene_render_settings.h"

#include "view/render_block.h"

namespace tissu {

RenderSettings render_settings_of(const Scene& scene) {
  const Json none = Json::object();
  try {
    JsonReader reader(scene.render.is_null() ? none : scene.render, "render");
    return parse_render_settings(reader, up_from_gravity(scene.gravity));
  } catch (const InputError& e) {
    throw scene_error(scene, e.what());
  }
}

RenderSettings still_render_settings(const Scene& scene, int width, int height) {
  RenderSettings settings = render_settings_of(scene);
  settings.width = width;
  settings.height = height;
  settings.caption.clear();
  settings.info = false;
  return settings;
}

}  // namespace tissu
