#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/mesh_readers.h"

namespace tissu {
namespace {

struct Corner {
  long long vertex;   // 1-based after resolving negative indices
  long long texture;  // 1-based, 0 when the corner has none
  long long vertex_as_written;
  long long texture_as_written;
};

struct Face {
  int line;
  int number;  // 1-based count of f statements
  std::vector<Corner> corners;
};

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

class ObjParser {
 public:
  ObjParser(const std::string& path, bool texture) : path_(path), texture_wanted_(texture) {}

  MeshFileData parse() {
    std::ifstream in(path_, std::ios::binary);
    if (!in) fail("cannot open: " + std::string(std::strerror(errno)));
    std::string text;
    while (std::getline(in, text)) {
      ++line_;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      statement(text);
    }
    if (in.bad()) fail("read error: " + std::string(std::strerror(errno)));
    return build();
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(path_ + ": " + problem);
  }
  [[noreturn]] void fail_line(const std::string& problem) const {
    fail("line " + std::to_string(line_) + ": " + problem);
  }
  static std::string face_place(const Face& f) {
    return "line " + std::to_string(f.line) + " (face " + std::to_string(f.number) + ")";
  }

  void statement(std::string_view text) {
    const size_t hash = text.find('#');
    if (hash != std::string_view::npos) text = text.substr(0, hash);
    const std::vector<std::string_view> words = split_words(text);
    if (words.empty()) return;
    if (words[0] == "v") {
      if (words.size() < 4) fail_line("a v statement needs 3 coordinates");
      positions_.emplace_back(number(words[1]), number(words[2]), number(words[3]));
    } else if (words[0] == "vt") {
      if (words.size() < 2) fail_line("a vt statement needs at least 1 coordinate");
      texture_.emplace_back(number(words[1]), words.size() > 2 ? number(words[2]) : 0.0);
    } else if (words[0] == "f") {
      face(words);
    }
  }

  double number(std::string_view word) const {
    std::string_view digits = word;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    double value = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error != std::errc() || end != digits.data() + digits.size()) {
      fail_line("cannot read '" + std::string(word) + "' as a number");
    }
    if (!std::isfinite(value)) fail_line("non-finite coordinate '" + std::string(word) + "'");
    return value;
  }

  // An index as written: 1-based, or negative to count back from the end.
  long long index(std::string_view word, const char* what) const {
    long long value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size() || value == 0) {
      fail("line " + std::to_string(line_) + " (face " + std::to_string(faces_.size() + 1) +
           "): cannot read '" + std::string(word) + "' as a " + what + " index");
    }
    return value;
  }
  // The 1-based index that `written` means when `count` items have been read so far.
  static long long resolve(long long written, size_t count) {
    return written < 0 ? static_cast<long long>(count) + written + 1 : written;
  }

  void face(const std::vector<std::string_view>& words) {
    Face f{line_, static_cast<int>(faces_.size()) + 1, {}};
    if (words.size() < 4) {
      fail(face_place(f) + ": a face needs at least 3 vertices, got " +
           std::to_string(words.size() - 1));
    }
    for (size_t k = 1; k < words.size(); ++k) {
      const std::string_view word = words[k];
      const size_t slash = word.find('/');
      Corner c{0, 0, index(word.substr(0, slash), "vertex"), 0};
      c.vertex = resolve(c.vertex_as_written, positions_.size());
      if (slash != std::string_view::npos) {
        const std::string_view rest = word.substr(slash + 1);
        const std::string_view texture = rest.substr(0, rest.find('/'));
        if (!texture.empty()) {
          c.texture_as_written = index(texture, "texture coordinate");
          c.texture = resolve(c.texture_as_written, texture_.size());
        }
      }
      f.corners.push_back(c);
    }
    faces_.push_back(std::move(f));
  }

  void check_indices(const Face& f, bool with_texture) const {
    for (const Corner& c : f.corners) {
      if (c.vertex < 1 || c.vertex > static_cast<long long>(positions_.size())) {
        fail(face_place(f) + ": vertex index " + std::to_string(c.vertex_as_written) +
             " out of range (file has " + std::to_string(positions_.size()) + " vertices)");
      }
      if (!texture_wanted_) continue;
      if ((c.texture_as_written != 0) != with_texture) {
        fail(face_place(f) + ": " + (with_texture ? "a corner has no" : "a corner has a") +
             " texture coordinate index, unlike " + face_place(faces_.front()) +
             " (give every face corner a vt index, or none)");
      }
      if (with_texture && (c.texture < 1 || c.texture > static_cast<long long>(texture_.size()))) {
        fail(face_place(f) + ": texture coordinate index " + std::to_string(c.texture_as_written) +
             " out of range (file has " + std::to_string(texture_.size()) +
             " texture coordinates)");
      }
    }
  }

  MeshFileData build() const {
    MeshFileData data;
    TriMesh& mesh = data.mesh;
    mesh.positions = positions_;
    const bool with_texture = texture_wanted_ && !faces_.empty() &&
                              faces_.front().corners.front().texture_as_written != 0;
    for (const Face& f : faces_) check_indices(f, with_texture);
    if (with_texture) assign_texture_coordinates(mesh);
    for (const Face& f : faces_) {
      const std::string place = face_place(f);
      for (size_t k = 1; k + 1 < f.corners.size(); ++k) {
        mesh.triangles.emplace_back(f.corners[0].vertex - 1, f.corners[k].vertex - 1,
                                    f.corners[k + 1].vertex - 1);
        data.triangle_places.push_back(place);
      }
    }
    return data;
  }

  // One (u, v) per vertex; a vertex whose corners disagree is a UV seam and is rejected.
  void assign_texture_coordinates(TriMesh& mesh) const {
    double extent = 0;
    for (const Vec2& t : texture_) extent = std::max(extent, t.cwiseAbs().maxCoeff());
    std::vector<const Face*> first_face(positions_.size(), nullptr);
    mesh.rest_uv.assign(positions_.size(), Vec2::Zero());
    mesh.uv_from_file = true;
    for (const Face& f : faces_) {
      for (const Corner& c : f.corners) {
        const size_t v = c.vertex - 1;
        const Vec2& uv = texture_[c.texture - 1];
        if (!first_face[v]) {
          first_face[v] = &f;
          mesh.rest_uv[v] = uv;
        } else if (!same_texture_coordinates(mesh.rest_uv[v], uv, extent)) {
          fail(face_place(f) + ": vertex index " + std::to_string(v + 1) + " has texture coordinates " +
               format_short(uv) + " here but " + format_short(mesh.rest_uv[v]) + " at " +
               face_place(*first_face[v]) + "; " + kSeamAdvice);
        }
      }
    }
  }

  const std::string& path_;
  bool texture_wanted_ = true;
  int line_ = 0;
  Vec3List positions_;
  Vec2List texture_;
  std::vector<Face> faces_;
};

}  // namespace

const char* const kSeamAdvice =
    "UV seams are not supported, the rest shape needs one (u, v) per vertex: give each side "
    "of the seam its own vertex, or remove the texture coordinates";

bool same_texture_coordinates(const Vec2& a, const Vec2& b, double extent) {
  return (a - b).cwiseAbs().maxCoeff() <= 1e-9 * std::max(extent, 1e-300);
}

MeshFileData read_obj(const std::string& path, bool texture) {
  return ObjParser(path, texture).parse();
}

}  // namespace tissu
