// Strict reading of one JSON object of a scene: every key is checked for type and range,
// and keys nobody asked for are errors (with the closest valid key suggested).
// Errors are InputError with the message "<json.path>: <problem>".
#pragma once

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/types.h"

namespace tissu {

using Json = nlohmann::json;

// A closed or half-open numeric interval used to validate values.
struct Range {
  double min = -1e300;
  double max = 1e300;
  bool min_open = false;  // value must be > min (not >=)
  bool max_open = false;

  static Range positive() { return {0.0, 1e300, true, false}; }
  static Range non_negative() { return {0.0, 1e300, false, false}; }
  static Range any() { return {}; }
  static Range between(double lo, double hi) { return {lo, hi, false, false}; }
};

class JsonReader {
 public:
  // `path` is the JSON path of `object` ("" for the document root).
  JsonReader(const Json& object, std::string path);

  const std::string& path() const { return path_; }
  std::string path_of(const std::string& key) const;
  bool has(const std::string& key) const;

  // Optional values return `fallback` when the key is absent; required ones throw.
  double number(const std::string& key, double fallback, Range range = Range::any());
  double number(const std::string& key, Range range = Range::any());
  long long integer(const std::string& key, long long fallback, Range range = Range::any());
  long long integer(const std::string& key, Range range = Range::any());
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback);
  std::string string(const std::string& key);
  std::string choice(const std::string& key, std::initializer_list<const char*> choices,
                     const std::string& fallback);
  std::string choice(const std::string& key, std::initializer_list<const char*> choices);
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback);
  std::string choice(const std::string& key, const std::vector<std::string>& choices);
  Vec3 vec3(const std::string& key, const Vec3& fallback);
  Vec3 vec3(const std::string& key);
  Vec2 vec2(const std::string& key, Range range = Range::any());
  std::vector<double> numbers(const std::string& key, size_t count, Range range = Range::any());

  // A nested object; the caller reads it with its own JsonReader and calls finish() on it.
  JsonReader object(const std::string& key);
  // The raw value (marks the key as known). Throws when absent.
  const Json& raw(const std::string& key);

  // Throws on the first key that was present but never read.
  void finish() const;

  // Mark a key as known without reading it (for keys read by another module).
  void accept(const std::string& key) { used_.insert(key); }

 private:
  const Json& require(const std::string& key);
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  const Json& object_;
  std::string path_;
  std::set<std::string> used_;
};

// Helpers for arrays of objects: the JSON path of element i of `key`.
std::string element_path(const std::string& array_path, size_t index);

// Checks a value of any JSON type against a numeric range; used by readers and overrides.
double checked_number(const Json& value, const std::string& path, Range range);
Vec3 checked_vec3(const Json& value, const std::string& path);

// The valid key closest to `key` by edit distance, or "" when none is close.
std::string closest_key(const std::string& key, const std::vector<std::string>& valid);

// Formats a double the way error messages print values (shortest round-trip form).
std::string format_number(double value);

}  // namespace tissu
