// tissu: cloth simulation and headless rendering from JSON scenes.
#include <iostream>
#include <string>
#include <vector>

#include "app/command_line.h"
#include "app/commands.h"
#include "core/error.h"
#include "render/render_error.h"

namespace {

const char* kHelp =
    "usage: tissu <command> [options]\n"
    "Commands:\n"
    "  run SCENE.json      simulate a scene; write a report and OBJ snapshots\n"
    "  render SCENE.json   simulate and render a scene to MP4 (and PNG) files\n"
    "  study SCENE.json    error against cost of every integrator over a ladder of time steps\n"
    "  stability SCENE.json...  largest stable time step of every integrator (bisection)\n"
    "  figure FIGURE.json...  render figure files (panels of runs, with captions) to PNG\n"
    "  paper               run the paper's experiments; write out/paper/paper-results.md/.csv\n"
    "  compare A B         compare two PNGs, frame directories or MP4s within a tolerance\n"
    "  batch BATCH.json    run a batch of scenes (a sweep of overrides) here or on Slurm\n"
    "  help                show this help\n"
    "Run `tissu <command> --help` for the options of a command.\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace tissu;
  set_command_line(std::vector<std::string>(argv, argv + argc));
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    std::cout << kHelp;
    return args.empty() ? kExitBadInput : kExitOk;
  }
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  try {
    if (args[0] == "run") return command_run(rest);
    if (args[0] == "render") return command_render(rest);
    if (args[0] == "study") return command_study(rest);
    if (args[0] == "stability") return command_stability(rest);
    if (args[0] == "figure") return command_figure(rest);
    if (args[0] == "paper") return command_paper(rest);
    if (args[0] == "compare") return command_compare(rest);
    if (args[0] == "batch") return command_batch(rest);
    std::cerr << "tissu: unknown command \"" << args[0] << "\" (see tissu --help)\n";
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const InputError& e) {
    std::cerr << "tissu: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const RenderError& e) {
    std::cerr << "tissu: renderer: " << e.what() << "\n";
    return kExitOutputError;
  } catch (const OutputError& e) {
    std::cerr << "tissu: " << e.what() << "\n";
    return kExitOutputError;
  } catch (const std::exception& e) {
    std::cerr << "tissu: internal error: " << e.what() << "\n";
    return kExitOutputError;
  }
}
