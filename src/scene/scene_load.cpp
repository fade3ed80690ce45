// Reading scene files and applying command-line overrides.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "scene/resolved_scene.h"
#include "scene/scene.h"

namespace tissu {

namespace {

// Line and column (1-based) of a byte offset in `text`.
std::pair<size_t, size_t> line_column(const std::string& text, size_t byte) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

// nlohmann's message without its "[json.exception...] " and "parse error at line L,
// column C: " prefixes.
std::string parse_reason(const std::string& what) {
  std::string reason = what;
  const size_t bracket = reason.find("] ");
  if (reason.rfind("[json.exception", 0) == 0 && bracket != std::string::npos) {
    reason = reason.substr(bracket + 2);
  }
  const size_t colon = reason.find(": ");
  if (reason.rfind("parse error", 0) == 0 && colon != std::string::npos) {
    reason = reason.substr(colon + 2);
  }
  return reason;
}

// nlohmann's DOM builder that keeps the byte offset and message of the first error instead
// of throwing: a number too large for a double ("1e999") is an out_of_range exception that
// carries no position, unlike syntax errors. It also stops at a key given twice in one
// object, which JSON parsers otherwise settle silently by keeping the last value, and
// names its place (`duplicate`: "cloth.mesh.triangles").
class LocatingParser : public nlohmann::detail::json_sax_dom_parser<Json> {
  using Base = nlohmann::detail::json_sax_dom_parser<Json>;

 public:
  explicit LocatingParser(Json& root) : Base(root, /*allow_exceptions=*/false) {}
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& /*token*/, const Exception& error) {
    error_position = position;
    error_message = error.what();
    return false;
  }
  bool start_object(std::size_t len) {
    open(false);
    return Base::start_object(len);
  }
  bool start_array(std::size_t len) {
    open(true);
    return Base::start_array(len);
  }
  bool end_object() {
    containers_.pop_back();
    return Base::end_object();
  }
  bool end_array() {
    containers_.pop_back();
    return Base::end_array();
  }
  bool key(std::string& name) {
    Container& c = containers_.back();
    if (!c.keys.insert(name).second) {
      duplicate = c.path.empty() ? name : c.path + "." + name;
      return false;
    }
    c.next = name;
    return Base::key(name);
  }
  bool null() {
    element();
    return Base::null();
  }
  bool boolean(bool b) {
    element();
    return Base::boolean(b);
  }
  bool number_integer(std::int64_t n) {
    element();
    return Base::number_integer(n);
  }
  bool number_unsigned(std::uint64_t n) {
    element();
    return Base::number_unsigned(n);
  }
  bool number_float(double x, const std::string& text) {
    element();
    return Base::number_float(x, text);
  }
  bool string(std::string& text) {
    element();
    return Base::string(text);
  }

  std::size_t error_position = 0;
  std::string error_message;
  std::string duplicate;  // the path of a key given twice, or empty

 private:
  struct Container {
    bool array = false;
    std::string path;              // "cloth.mesh", "obstacles[1]"
    std::set<std::string> keys;    // an object's keys so far
    std::string next;              // an object's key of the value to come
    int index = -1;                // an array's element so far
  };
  // A value inside the current container: an array counts it (an object has named it).
  void element() {
    if (!containers_.empty() && containers_.back().array) ++containers_.back().index;
  }
  // An object or array opens: its path is only spelled out here, for the error message.
  void open(bool array) {
    element();
    Container c;
    c.array = array;
    if (!containers_.empty()) {
      const Container& parent = containers_.back();
      c.path = parent.array ? parent.path + "[" + std::to_string(parent.index) + "]"
               : parent.path.empty() ? parent.next
                                     : parent.path + "." + parent.next;
    }
    containers_.push_back(std::move(c));
  }
  std::vector<Container> containers_;
};

// ": NaN and Infinity ..." when the JSON error is at a NaN or Infinity literal, which
// JavaScript and Python write but JSON does not allow.
std::string non_finite_hint(const std::string& text, size_t byte) {
  size_t start = std::min(byte > 0 ? byte - 1 : 0, text.size());
  auto in_word = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; };
  while (start > 0 && in_word(text[start - 1])) --start;
  size_t end = start;
  while (end < text.size() && in_word(text[end])) ++end;
  std::string word = text.substr(start, end - start);
  for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (word == "nan" || word == "inf" || word == "infinity") {
    return " (NaN and Infinity are not JSON numbers: give a finite number)";
  }
  return "";
}

bool is_index(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(c); });
}

}  // namespace

Json read_scene_json(const std::string& file) {
  std::error_code ignored;
  if (std::filesystem::is_directory(file, ignored)) {
    throw InputError(file + ": cannot open scene file: is a directory");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open scene file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(file + ": cannot read scene file");
  const std::string text = buffer.str();
  Json doc;
  LocatingParser parser(doc);
  if (!Json::sax_parse(text, &parser, Json::input_format_t::json, /*strict=*/true,
                       /*ignore_comments=*/true)) {
    if (!parser.duplicate.empty()) {
      throw InputError(file + ": " + parser.duplicate + ": given twice (each key of an "
                       "object once)");
    }
    const size_t byte = parser.error_position;
    const auto [line, column] = line_column(text, byte > 0 ? byte - 1 : 0);
    throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(column) +
                     ": not valid JSON: " + parse_reason(parser.error_message) +
                     non_finite_hint(text, byte));
  }
  return doc;
}

void apply_override(Json& doc, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError("--set " + assignment + ": expected KEY=VALUE, e.g. --set dt=1e-4");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  Json value;
  try {
    value = Json::parse(text);
  } catch (const Json::out_of_range&) {
    throw InputError("--set " + assignment + ": " + text + " is out of the range of a double");
  } catch (const Json::parse_error&) {
    value = text;  // not JSON: a string
  }

  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) throw InputError("--set " + assignment + ": empty key segment");
    parts.push_back(part);
  }
  Json* node = &doc;
  std::string walked;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    walked += (walked.empty() ? "" : ".") + part;
    if (node->is_array()) {
      // At most 18 digits: std::stoull would throw on an index beyond 2^64.
      if (!is_index(part) || part.size() > 18 || std::stoull(part) >= node->size()) {
        throw InputError("--set " + assignment + ": " + walked + " is not an element of an "
                         "array of " + std::to_string(node->size()));
      }
      node = &(*node)[std::stoull(part)];
    } else if (node->is_object()) {
      if (!last && !node->contains(part)) (*node)[part] = Json::object();
      node = &(*node)[part];
      // A preset name overridden field by field becomes the preset-plus-fields form.
      if (!last && walked == "cloth.material" && node->is_string()) {
        *node = Json{{"preset", node->get<std::string>()}};
      }
    } else {
      throw InputError("--set " + assignment + ": " + walked + " is inside a value that is "
                       "not an object");
    }
  }
  *node = value;
  // steps and duration say the same thing: the one overridden replaces the other.
  if (doc.is_object() && parts.size() == 1 && (key == "steps" || key == "duration")) {
    doc.erase(key == "steps" ? "duration" : "steps");
  }
}

namespace {

// The override among `overrides` that set the value `message` ("<json.path>: ...") is
// about, or nullptr.
const std::string* override_named_by(const std::vector<std::string>& overrides,
                                     const std::string& message) {
  std::string dotted = message.substr(0, message.find(':'));
  for (char& c : dotted) c = (c == '[' || c == ']') ? '.' : c;
  dotted.erase(std::unique(dotted.begin(), dotted.end(),
                           [](char a, char b) { return a == '.' && b == '.'; }),
               dotted.end());
  if (!dotted.empty() && dotted.back() == '.') dotted.pop_back();
  for (const std::string& o : overrides) {
    const std::string key = o.substr(0, o.find('='));
    if (dotted == key || dotted.rfind(key + ".", 0) == 0) return &o;
  }
  return nullptr;
}

InputError named_scene_error(const std::string& file, const std::vector<std::string>& overrides,
                             const std::string& message) {
  if (const std::string* o = override_named_by(overrides, message)) {
    return InputError("--set " + *o + ": " + message);
  }
  return InputError(file.empty() ? message : file + ": " + message);
}

}  // namespace

Scene load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  Json doc = read_scene_json(file);
  for (const std::string& o : overrides) apply_override(doc, o);
  Scene scene;
  try {
    scene = parse_scene(doc, file);
  } catch (const InputError& e) {
    throw named_scene_error(file, overrides, e.what());
  }
  scene.overrides = overrides;
  scene.resolved = resolved_scene(doc, scene);
  return scene;
}

InputError scene_error(const Scene& scene, const std::string& message) {
  return named_scene_error(scene.file, scene.overrides, message);
}

}  // namespace tissu
