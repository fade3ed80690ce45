#include "video/partial_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

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

void write_text_file(const std::string& path, const std::string& text) {
  const std::string partial = partial_path_for(path);
  FILE* file = std::fopen(partial.c_str(), "wb");
  if (!file) throw OutputError(path + ": cannot write: " + errno_text(errno));
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  const int write_errno = errno;
  if (std::fclose(file) != 0 || !written) {
    discard_partial_file(partial);
    throw OutputError(path + ": cannot write: " + errno_text(written ? errno : write_errno));
  }
  commit_partial_file(partial, path);
}

}  // namespace tissu
