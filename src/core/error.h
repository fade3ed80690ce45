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

// Bad use of a command, reported by the command itself: the message starts with it
// ("tissu render: unknown option --fast (see tissu render --help)") and is printed as it is.
// Exit code 2.
struct UsageError : InputError {
  using InputError::InputError;
};

// A failure while producing output (disk full, encoder error). Exit code 1.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tissu
