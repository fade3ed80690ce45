// The text of a libav error code, for messages. Private to src/video.
#pragma once

extern "C" {
#include <libavutil/error.h>
}

#include <string>

namespace tissu {

inline std::string av_error_text(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = "";
  if (av_strerror(code, text, sizeof text) < 0) return "libav error " + std::to_string(code);
  return text;
}

}  // namespace tissu
