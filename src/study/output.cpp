#include "study/output.h"

#include <cerrno>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "video/partial_file.h"

namespace tissu {

std::string sig(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, value);
  return buf;
}

}  // namespace tissu
