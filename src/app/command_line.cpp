#include "app/command_line.h"

#include <utility>

namespace tissu {

namespace {

std::vector<std::string>& stored() {
  static std::vector<std::string> argv;
  return argv;
}

}  // namespace

void set_command_line(std::vector<std::string> argv) { stored() = std::move(argv); }

const std::vector<std::string>& command_line() { return stored(); }

}  // namespace tissu
