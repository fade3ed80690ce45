// Output files are written under a temporary name and renamed over their final path
// (core/partial_file.h). That rename must never replace something that is not an output
// file: as root, renaming onto /dev/full would put a regular file in place of the device.
#pragma once

#include <sys/stat.h>

#include <string>

#include "core/error.h"

namespace tissu {

// "character device", "directory", ... for the file type in `mode`.
inline const char* file_type_name(mode_t mode) {
  if (S_ISREG(mode)) return "regular file";
  if (S_ISDIR(mode)) return "directory";
  if (S_ISCHR(mode)) return "character device";
  if (S_ISBLK(mode)) return "block device";
  if (S_ISFIFO(mode)) return "named pipe";
  if (S_ISSOCK(mode)) return "socket";
  if (S_ISLNK(mode)) return "symbolic link";
  return "special file";
}

// Throws OutputError ("PATH: cannot write: not a regular file (character device)") unless
// an output file may be renamed onto `path`: nothing is there, or a regular file. Anything
// else is refused and left untouched: a device, named pipe, socket or directory, and a
// symbolic link of any kind, which the rename would replace (/dev/stdout, whose target may
// well be a regular file, is such a link).
inline void check_output_target(const std::string& path) {
  struct stat link {};
  if (::lstat(path.c_str(), &link) != 0) return;  // absent, or the rename will say why
  if (S_ISREG(link.st_mode)) return;
  if (S_ISLNK(link.st_mode)) {
    struct stat target {};
    const std::string what = ::stat(path.c_str(), &target) != 0
                                 ? std::string("dangling symbolic link")
                                 : std::string("symbolic link to a ") + file_type_name(target.st_mode);
    throw OutputError(path + ": cannot write: not a regular file (" + what + ")");
  }
  throw OutputError(path + ": cannot write: not a regular file (" +
                    file_type_name(link.st_mode) + ")");
}

}  // namespace tissu
