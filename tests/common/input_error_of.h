// The message of the InputError a piece of code throws, for tests of one-line errors.
#pragma once

#include <functional>
#include <string>

#include "core/error.h"

namespace tissu::test {

// The message of the InputError `f` throws, or "" when it throws none.
inline std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace tissu::test
