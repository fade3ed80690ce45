// The command line the program was started with, as given (argv), for run reports.
#pragma once

#include <string>
#include <vector>

namespace tissu {

void set_command_line(std::vector<std::string> argv);

// Empty when set_command_line was never called (commands driven from tests).
const std::vector<std::string>& command_line();

}  // namespace tissu
