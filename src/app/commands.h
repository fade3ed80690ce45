// The subcommands of the tissu program. Each returns the process exit code.
#pragma once

#include <string>
#include <vector>

namespace tissu {

int command_run(const std::vector<std::string>& args);
int command_render(const std::vector<std::string>& args);
int command_study(const std::vector<std::string>& args);
int command_stability(const std::vector<std::string>& args);
int command_figure(const std::vector<std::string>& args);
int command_paper(const std::vector<std::string>& args);
int command_compare(const std::vector<std::string>& args);
int command_batch(const std::vector<std::string>& args);

// Exit code of a finished run.
constexpr int kExitOk = 0;
constexpr int kExitOutputError = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitDiverged = 3;
constexpr int kExitCrossings = 4;  // --check found triangles that cross
constexpr int kExitInterrupted = 130;

// Exit code of `tissu compare` when frames differ beyond tolerance (bad input is still 2).
constexpr int kExitDifferent = 1;

}  // namespace tissu
