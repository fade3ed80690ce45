// The current time in UTC as text, for reports and generated documents.
#pragma once

#include <ctime>
#include <string>

namespace tissu {

// std::strftime `format` of the current UTC time, e.g. "%Y-%m-%dT%H:%M:%SZ".
inline std::string utc_now(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char out[64];
  std::strftime(out, sizeof out, format, &tm);
  return out;
}

}  // namespace tissu
