// Writing the study's text outputs and formatting their numbers.
#pragma once

#include <string>

#include "video/partial_file.h"  // write_text_file

namespace tissu {


// Number with `digits` significant digits in the shortest of fixed or exponent form ("%.3g").
std::string sig(double value, int digits = 3);

}  // namespace tissu
