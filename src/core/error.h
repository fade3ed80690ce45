// Errors the program reports to its user as one line.
#pragma once

#include <stdexcept>
#include <string>

namespace tissu {

// Bad input: scene, override, mesh or command line. Exit code 2.
// The message names the place (file, JSON path, line, mesh element) and the problem.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A failure while producing output (disk full, encoder error). Exit code 1.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tissu
