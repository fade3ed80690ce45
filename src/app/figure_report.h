// The report of one `tissu figure` image (<image stem>.report.json beside it): what was
// drawn and the wall times measured, which the image itself leaves out by default so that
// it is the same bits on every run.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "figure/figure.h"

namespace tissu {

nlohmann::ordered_json make_figure_report(const FigureSpec& figure, const FigureResult& result,
                                          const std::string& image_path);

// Where the report of the image `image_path` goes: the same name, ".report.json" for ".png".
std::string figure_report_path(const std::string& image_path);

}  // namespace tissu
