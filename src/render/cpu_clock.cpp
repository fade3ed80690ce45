#include "render/cpu_clock.h"

#include <filesystem>
#include <fstream>

namespace tissu {

double named_threads_cpu_seconds(const std::string& prefix) {
  namespace fs = std::filesystem;
  double total = 0.0;
  std::error_code error;
  for (const fs::directory_entry& task : fs::directory_iterator("/proc/self/task", error)) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (!std::getline(comm, name) || name.compare(0, prefix.size(), prefix) != 0) continue;
    std::ifstream schedstat(task.path() / "schedstat");
    long long on_cpu_ns = 0;  // first field: time spent on the CPU, ns
    if (schedstat >> on_cpu_ns) total += 1e-9 * static_cast<double>(on_cpu_ns);
  }
  return total;
}

}  // namespace tissu
