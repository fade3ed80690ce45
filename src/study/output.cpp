#include "study/output.h"

#include <cerrno>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "video/partial_file.h"

namespace tissu {

void write_text_output(const std::string& path, const std::string& text) {
  const std::string partial = partial_path_for(path);
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError(path + ": cannot write: " + errno_text(errno));
    out << text;
    out.close();
    if (!out) {
      discard_partial_file(partial);
      throw OutputError(path + ": write failed: " + errno_text(errno));
    }
  }
  commit_partial_file(partial, path);
}

std::string sig(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, value);
  return buf;
}

}  // namespace tissu
