#include "mesh/obj_writer.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "core/output_target.h"

namespace tissu {
namespace {

// Buffered writer of one temporary file; any failure removes it and throws.
class TempFile {
 public:
  TempFile(const std::string& path, const std::string& temp) : path_(path), temp_(temp) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) fail("cannot create " + temp_);
  }
  ~TempFile() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }

  void text(const char* s, size_t n) {
    if (std::fwrite(s, 1, n, file_) != n) fail("write failed");
  }
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

  // Flushes, closes and renames over the target.
  void commit() {
    if (std::fflush(file_) != 0) fail("write failed");
    std::FILE* file = file_;
    file_ = nullptr;
    if (std::fclose(file) != 0) fail("close failed");
    try {
      check_output_target(path_);  // never rename over a device, pipe, directory or link
    } catch (...) {
      std::remove(temp_.c_str());
      throw;
    }
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail("cannot rename " + temp_ + " to it");
    committed_ = true;
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    const int error = errno;
    if (file_) std::fclose(file_);
    file_ = nullptr;
    std::remove(temp_.c_str());
    throw OutputError(path_ + ": " + what + ": " +
                      (error != 0 ? std::strerror(error) : "unknown reason"));
  }

  const std::string& path_;
  std::string temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
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
  TempFile out(path, path + ".tmp");
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
