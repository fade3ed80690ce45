#include "render/frame_content.h"

#include <cstdio>

namespace tissu {

std::vector<std::string> info_overlay_lines(const std::string& integrator, size_t triangle_count,
                                            double time_s) {
  char time[64];
  std::snprintf(time, sizeof time, "t = %.3f s", time_s);
  return {"integrator: " + integrator, "triangles: " + std::to_string(triangle_count), time};
}

}  // namespace tissu
