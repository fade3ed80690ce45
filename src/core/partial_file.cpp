#include "core/partial_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "core/error.h"
#include "core/output_target.h"

namespace tissu {

std::string partial_path_for(const std::string& final_path) {
  const std::size_t slash = final_path.rfind('/');
  const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
  return final_path.substr(0, name_start) + "." + final_path.substr(name_start) + ".partial";
}

std::string errno_text(int error_number) {
  char buffer[256];
  // GNU strerror_r returns the message pointer, which may or may not be `buffer`.
  return strerror_r(error_number, buffer, sizeof buffer);
}

void commit_partial_file(const std::string& partial_path, const std::string& final_path) {
  try {
    check_output_target(final_path);  // never rename over a device, pipe, directory or link
  } catch (...) {
    discard_partial_file(partial_path);
    throw;
  }
  if (std::rename(partial_path.c_str(), final_path.c_str()) != 0) {
    const int error_number = errno;
    discard_partial_file(partial_path);
    throw OutputError(final_path + ": cannot move the finished file into place: " + errno_text(error_number));
  }
}

void discard_partial_file(const std::string& partial_path) noexcept { ::unlink(partial_path.c_str()); }

void sync_file_to_disk(const std::string& path, const std::string& final_path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int error_number = errno;
    if (fd >= 0) ::close(fd);
    throw OutputError(final_path + ": cannot flush to disk: " + errno_text(error_number));
  }
  ::close(fd);
}

PartialFile::PartialFile(std::string final_path)
    : final_path_(std::move(final_path)), partial_path_(partial_path_for(final_path_)) {
  file_ = std::fopen(partial_path_.c_str(), "wb");
  if (!file_) throw OutputError(final_path_ + ": cannot write: " + errno_text(errno));
}

PartialFile::~PartialFile() {
  if (file_) std::fclose(file_);
  if (!committed_) discard_partial_file(partial_path_);
}

void PartialFile::write(const char* data, std::size_t size) {
  if (std::fwrite(data, 1, size, file_) != size) fail(errno);
}

void PartialFile::commit() {
  if (std::fflush(file_) != 0) fail(errno);
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0) fail(errno);
  commit_partial_file(partial_path_, final_path_);
  committed_ = true;
}

void PartialFile::fail(int error_number) {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  discard_partial_file(partial_path_);
  throw OutputError(final_path_ + ": cannot write: " + errno_text(error_number));
}

void write_text_file(const std::string& path, const std::string& text) {
  PartialFile file(path);
  file.write(text.data(), text.size());
  file.commit();
}

}  // namespace tissu
