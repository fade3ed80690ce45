// Short number formatting for messages of the mesh module.
#pragma once

#include <cstdio>
#include <string>

#include "core/types.h"

namespace tissu {

inline std::string format_short(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

inline std::string format_short(const Vec2& v) {
  return "(" + format_short(v.x()) + ", " + format_short(v.y()) + ")";
}

inline std::string format_short(const Vec3& v) {
  return "(" + format_short(v.x()) + ", " + format_short(v.y()) + ", " + format_short(v.z()) + ")";
}

}  // namespace tissu
