#include "mesh/obj_writer.h"

#include <charconv>
#include <stdexcept>

#include "core/partial_file.h"

namespace tissu {
namespace {

// OBJ text into a file written under its temporary name (core/partial_file.h).
class ObjText {
 public:
  explicit ObjText(const std::string& path) : file_(path) {}

  void text(const char* s, size_t n) { file_.write(s, n); }
  void number(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    text(buffer, result.ptr - buffer);
  }
  void number(long long value) {
    char buffer[24];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    text(buffer, result.ptr - buffer);
  }
  void commit() { file_.commit(); }

 private:
  PartialFile file_;
};

}  // namespace

void write_obj(const std::string& path, const Vec3List& positions, const Vec2List& rest_uv,
               const TriList& triangles) {
  if (!rest_uv.empty() && rest_uv.size() != positions.size()) {
    throw std::invalid_argument("write_obj: rest_uv and positions differ in length");
  }
  for (const Tri& t : triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= static_cast<int>(positions.size())) {
      throw std::invalid_argument("write_obj: vertex id out of range");
    }
  }
  ObjText out(path);
  static const char header[] = "# written by tissu: positions in m, vt = rest (u, v) in m\n";
  out.text(header, sizeof header - 1);
  for (const Vec3& p : positions) {
    out.text("v ", 2);
    for (int k = 0; k < 3; ++k) {
      out.number(p[k]);
      out.text(k < 2 ? " " : "\n", 1);
    }
  }
  for (const Vec2& uv : rest_uv) {
    out.text("vt ", 3);
    out.number(uv.x());
    out.text(" ", 1);
    out.number(uv.y());
    out.text("\n", 1);
  }
  const bool with_uv = !rest_uv.empty();
  for (const Tri& t : triangles) {
    out.text("f", 1);
    for (int k = 0; k < 3; ++k) {
      const long long id = t[k] + 1LL;
      out.text(" ", 1);
      out.number(id);
      if (with_uv) {
        out.text("/", 1);
        out.number(id);
      }
    }
    out.text("\n", 1);
  }
  out.commit();
}

}  // namespace tissu
