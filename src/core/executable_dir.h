// The directory of the running program, for files installed beside it (shaders, data).
#pragma once

#include <unistd.h>

#include <string>
#include <vector>

namespace tissu {

// "" when it cannot be found.
inline std::string executable_dir() {
  std::vector<char> buffer(4096);
  const ssize_t n = readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  if (n <= 0) return "";
  const std::string path(buffer.data(), static_cast<size_t>(n));
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}

}  // namespace tissu
