#include "render/render_settings.h"

namespace tissu {

std::vector<Light> RenderSettings::default_lights() {
  // Key light from above-left-front of the default camera, soft cool fill from the right.
  Light key{Vec3(0.5, 1.5, -1.75), Vec3(1.0, 0.97, 0.92), 1.0};
  Light fill{Vec3(-1.7, 0.4, -0.75), Vec3(0.85, 0.9, 1.0), 0.35};
  return {key, fill};
}

}  // namespace tissu
