#include "study/output.h"

#include <cstdio>

namespace tissu {

namespace {

std::string table_line(const std::vector<std::string>& cells) {
  std::string out = "|";
  for (const std::string& c : cells) out += " " + c + " |";
  return out + "\n";
}

}  // namespace

std::string sig(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, value);
  return buf;
}

std::string printf_text(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, value);
  return buf;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string MarkdownTable::text() const {
  std::string out = table_line(header_);
  std::string separator = "|";
  for (size_t i = 0; i < header_.size(); ++i) separator += " --- |";
  out += separator + "\n";
  for (const auto& r : rows_) out += table_line(r);
  return out + "\n";
}

}  // namespace tissu
