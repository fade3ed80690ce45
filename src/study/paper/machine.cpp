#include "study/paper/machine.h"

#include <cstdio>
#include <fstream>
#include <thread>

#include "study/output.h"

namespace tissu {

namespace {

// The value of the first "name : value" line of /proc/cpuinfo, or "unknown".
std::string cpu_field(const std::string& name) {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(name, 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::string v = line.substr(colon + 1);
        v.erase(0, v.find_first_not_of(" \t"));
        return v;
      }
    }
  }
  return "unknown";
}

int cpu_processors() {
  std::ifstream in("/proc/cpuinfo");
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind("processor", 0) == 0;
  return n;
}

// What a shell command prints, without its trailing newlines; empty when it fails.
std::string command_output(const char* command) {
  std::string out;
  if (FILE* p = popen(command, "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string build_type() {
#ifdef NDEBUG
  return ", optimised build";
#else
  return ", **debug build (times not representative)**";
#endif
}

}  // namespace

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return printf_text("%.2f", one) + " / " + printf_text("%.2f", five) + " / " +
         printf_text("%.2f", fifteen);
}

std::string machine_description() {
  const std::string commit = command_output("git rev-parse --short HEAD 2>/dev/null");
  const std::string dirty =
      command_output("git status --porcelain --untracked-files=no 2>/dev/null");
  return "Machine: " + cpu_field("model name") + ", " + std::to_string(cpu_processors()) +
         " logical processors in /proc/cpuinfo (`cpu cores`: " + cpu_field("cpu cores") +
         "), " + std::to_string(std::thread::hardware_concurrency()) +
         " available to this process; the simulation runs on one thread. Compiler: " +
         std::string(__VERSION__) + build_type() +
         (commit.empty() ? std::string()
                         : ". Source: git " + commit + (dirty.empty() ? "" : " with local changes")) +
         ". Load average (1 / 5 / 15 min) at the start: " + load_average() +
         " (other processes share the machine: wall times above the single-run minimum "
         "reflect them).\nThe paper's machine: Intel Core i5 680 @ 3.60 GHz, 4 GB RAM.\n\n";
}

}  // namespace tissu
