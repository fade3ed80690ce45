// A description of the machine the experiments ran on, for the paper's results document.
#pragma once

#include <string>

namespace tissu {

// Processor, logical processors, compiler and build type, git commit of the working
// directory, and the load average: one paragraph ending with the paper's machine.
std::string machine_description();

// The 1 / 5 / 15 minute load averages ("0.52 / 0.61 / 0.70"), or "unknown".
std::string load_average();

}  // namespace tissu
