// Writing the study's text outputs and formatting their numbers and tables.
#pragma once

#include <string>
#include <vector>

#include "core/partial_file.h"  // write_text_file

namespace tissu {

// Number with `digits` significant digits in the shortest of fixed or exponent form ("%.3g").
std::string sig(double value, int digits = 3);

// A value formatted with one printf conversion ("%.3f", "%.1e").
std::string printf_text(const char* format, double value);

// A CSV field, quoted (with doubled quotes) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text);

// A Markdown table: a header row, the separator, the rows, and a blank line after it.
class MarkdownTable {
 public:
  explicit MarkdownTable(std::vector<std::string> header) : header_(std::move(header)) {}
  void row(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }
  std::string text() const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace tissu
