// Output files appear complete or not at all: they are written under a hidden temporary
// name in the same directory ("out/.demo.mp4.partial" for "out/demo.mp4") and renamed
// into place once complete. A rename within one directory is atomic on POSIX systems.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

namespace tissu {

// "dir/name" -> "dir/.name.partial".
std::string partial_path_for(const std::string& final_path);

// Renames the finished temporary file onto the final path; throws OutputError naming
// `final_path` and the system's reason. The temporary file is removed on failure. A final
// path that is not a regular file (device, named pipe, socket, directory, symbolic link) is
// refused, never replaced (core/output_target.h).
void commit_partial_file(const std::string& partial_path, const std::string& final_path);

// Removes the temporary file if it exists; never throws.
void discard_partial_file(const std::string& partial_path) noexcept;

// Flushes a closed file's data to the disk (so a power loss after the rename cannot
// leave an empty final file); throws OutputError naming `final_path`.
void sync_file_to_disk(const std::string& path, const std::string& final_path);

// A file being written under its temporary name: write() appends, commit() renames it
// onto the final path. Any failure, or destruction before commit(), removes the
// temporary file, so the final path keeps what it had before.
class PartialFile {
 public:
  // Creates the temporary file of `final_path`; throws OutputError
  // "<final_path>: cannot write: <reason>".
  explicit PartialFile(std::string final_path);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  // Appends `size` bytes; throws OutputError as the constructor.
  void write(const char* data, std::size_t size);
  // Flushes and closes the file, then commit_partial_file.
  void commit();

 private:
  [[noreturn]] void fail(int error_number);

  std::string final_path_;
  std::string partial_path_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Writes `text` to `path` through the temporary file, so the file appears complete or not
// at all; throws OutputError "<path>: cannot write: <reason>".
void write_text_file(const std::string& path, const std::string& text);

// strerror text for errno values, thread-safe.
std::string errno_text(int error_number);

}  // namespace tissu
