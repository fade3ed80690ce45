// Words for a POSIX shell command line: in scripts Tissu writes, and in commands it
// suggests to the user.
#pragma once

#include <string>

namespace tissu {

// `text` in single quotes for /bin/sh, always.
std::string shell_quote(const std::string& text);

// `text` as it is when the shell reads it as one word unchanged (letters, digits and
// ._-/=,:+), else shell_quote(text): for commands a person reads.
std::string shell_word(const std::string& text);

}  // namespace tissu
