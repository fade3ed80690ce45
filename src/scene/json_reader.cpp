#include "scene/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace tissu {

namespace {

const char* type_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::string: return "a string";
    case Json::value_t::array: return "an array";
    case Json::value_t::object: return "an object";
    case Json::value_t::discarded: return "invalid";
    default: return "a number";
  }
}

std::string describe_range(const Range& r) {
  std::ostringstream s;
  const bool has_min = r.min > -1e299, has_max = r.max < 1e299;
  if (has_min && has_max) {
    s << "be in " << (r.min_open ? "(" : "[") << format_number(r.min) << ", "
      << format_number(r.max) << (r.max_open ? ")" : "]");
  } else if (has_min) {
    s << "be " << (r.min_open ? "> " : ">= ") << format_number(r.min);
  } else {
    s << "be " << (r.max_open ? "< " : "<= ") << format_number(r.max);
  }
  return s.str();
}

bool in_range(double x, const Range& r) {
  if (r.min_open ? !(x > r.min) : !(x >= r.min)) return false;
  if (r.max_open ? !(x < r.max) : !(x <= r.max)) return false;
  return true;
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string format_number(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "Infinity" : "-Infinity";
  if (value == std::floor(value) && std::fabs(value) < 1e15) {
    return std::to_string(static_cast<long long>(value));
  }
  std::ostringstream s;
  s.precision(15);
  s << value;
  std::string text = s.str();
  // Shorten 0.10000000000000001-style noise.
  for (int p = 1; p <= 17; ++p) {
    std::ostringstream t;
    t.precision(p);
    t << value;
    // strtod, not std::stod: "2e+308" (1.7e308 at precision 1) overflows, and stod throws.
    if (std::strtod(t.str().c_str(), nullptr) == value) return t.str();
  }
  return text;
}

std::string closest_key(const std::string& key, const std::vector<std::string>& valid) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, key.size() / 3) + 1;
  for (const std::string& candidate : valid) {
    const size_t d = edit_distance(key, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

std::string element_path(const std::string& array_path, size_t index) {
  return array_path + "[" + std::to_string(index) + "]";
}

double checked_number(const Json& value, const std::string& path, Range range) {
  if (!value.is_number()) {
    throw InputError(path + ": must be a number, got " + type_name(value));
  }
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw InputError(path + ": must be finite, got " + format_number(x));
  if (!in_range(x, range)) {
    throw InputError(path + ": must " + describe_range(range) + ", got " + format_number(x));
  }
  return x;
}

Vec3 checked_vec3(const Json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3) {
    throw InputError(path + ": must be an array of 3 numbers, got " +
                     (value.is_array() ? "an array of " + std::to_string(value.size())
                                       : std::string(type_name(value))));
  }
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = checked_number(value[i], element_path(path, i), Range::any());
  return v;
}

JsonReader::JsonReader(const Json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw InputError((path_.empty() ? std::string("scene") : path_) + ": must be an object, got " +
                     type_name(object_));
  }
}

std::string JsonReader::path_of(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool JsonReader::has(const std::string& key) const { return object_.contains(key); }

void JsonReader::fail(const std::string& key, const std::string& problem) const {
  throw InputError(path_of(key) + ": " + problem);
}

const Json& JsonReader::require(const std::string& key) {
  used_.insert(key);
  auto it = object_.find(key);
  if (it == object_.end()) fail(key, "is required");
  return *it;
}

double JsonReader::number(const std::string& key, double fallback, Range range) {
  used_.insert(key);
  return has(key) ? checked_number(object_.at(key), path_of(key), range) : fallback;
}

double JsonReader::number(const std::string& key, Range range) {
  return checked_number(require(key), path_of(key), range);
}

long long JsonReader::integer(const std::string& key, long long fallback, Range range) {
  used_.insert(key);
  return has(key) ? integer(key, range) : fallback;
}

long long JsonReader::integer(const std::string& key, Range range) {
  const Json& v = require(key);
  const double x = checked_number(v, path_of(key), range);
  if (x != std::floor(x) || std::fabs(x) > 9e15) {
    fail(key, "must be an integer, got " + format_number(x));
  }
  return static_cast<long long>(x);
}

bool JsonReader::boolean(const std::string& key, bool fallback) {
  used_.insert(key);
  if (!has(key)) return fallback;
  const Json& v = object_.at(key);
  if (!v.is_boolean()) fail(key, std::string("must be true or false, got ") + type_name(v));
  return v.get<bool>();
}

std::string JsonReader::string(const std::string& key, const std::string& fallback) {
  used_.insert(key);
  return has(key) ? string(key) : fallback;
}

std::string JsonReader::string(const std::string& key) {
  const Json& v = require(key);
  if (!v.is_string()) fail(key, std::string("must be a string, got ") + type_name(v));
  return v.get<std::string>();
}

std::string JsonReader::choice(const std::string& key, std::initializer_list<const char*> choices,
                               const std::string& fallback) {
  return choice(key, std::vector<std::string>(choices.begin(), choices.end()), fallback);
}

std::string JsonReader::choice(const std::string& key,
                               std::initializer_list<const char*> choices) {
  return choice(key, std::vector<std::string>(choices.begin(), choices.end()));
}

std::string JsonReader::choice(const std::string& key, const std::vector<std::string>& choices,
                               const std::string& fallback) {
  used_.insert(key);
  return has(key) ? choice(key, choices) : fallback;
}

std::string JsonReader::choice(const std::string& key, const std::vector<std::string>& valid) {
  const std::string value = string(key);
  if (std::find(valid.begin(), valid.end(), value) != valid.end()) return value;
  std::string list;
  for (const std::string& c : valid) list += (list.empty() ? "" : ", ") + c;
  const std::string near = closest_key(value, valid);
  fail(key, "unknown value \"" + value + "\"" +
                (near.empty() ? "" : " (did you mean \"" + near + "\"?)") + "; expected one of " +
                list);
}

Vec3 JsonReader::vec3(const std::string& key, const Vec3& fallback) {
  used_.insert(key);
  return has(key) ? vec3(key) : fallback;
}

Vec3 JsonReader::vec3(const std::string& key) { return checked_vec3(require(key), path_of(key)); }

Vec2 JsonReader::vec2(const std::string& key, Range range) {
  const std::vector<double> v = numbers(key, 2, range);
  return Vec2(v[0], v[1]);
}

std::vector<double> JsonReader::numbers(const std::string& key, size_t count, Range range) {
  const Json& v = require(key);
  if (!v.is_array() || v.size() != count) {
    fail(key, "must be an array of " + std::to_string(count) + " numbers, got " +
                  (v.is_array() ? "an array of " + std::to_string(v.size())
                                : std::string(type_name(v))));
  }
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i) {
    out.push_back(checked_number(v[i], element_path(path_of(key), i), range));
  }
  return out;
}

JsonReader JsonReader::object(const std::string& key) {
  return JsonReader(require(key), path_of(key));
}

const Json& JsonReader::raw(const std::string& key) { return require(key); }

void JsonReader::finish() const {
  std::vector<std::string> valid(used_.begin(), used_.end());
  for (auto it = object_.begin(); it != object_.end(); ++it) {
    if (used_.count(it.key())) continue;
    const std::string near = closest_key(it.key(), valid);
    fail(it.key(), "unknown key" + (near.empty() ? std::string() : " (did you mean \"" +
                                                                        path_of(near) + "\"?)"));
  }
}

}  // namespace tissu
