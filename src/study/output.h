// Writing the study's text outputs and formatting their numbers.
#pragma once

#include <string>

namespace tissu {

// Writes `text` to `path`: the file appears complete or not at all (temporary file, then
// rename). Throws OutputError naming `path`.
void write_text_output(const std::string& path, const std::string& text);

// Number with `digits` significant digits in the shortest of fixed or exponent form ("%.3g").
std::string sig(double value, int digits = 3);

}  // namespace tissu
