// read_with_assimp: assimp (a prebuilt library that hung or aborted on malformed files found
// by fuzzing) reads the file in a child process with a time limit. The child sends its
// result through a pipe in a simple binary form:
//   u8 status: 0 = read, 1 = InputError, 2 = another exception
//   status 0: u8 uv_from_file, u8 file_vertex_ids, u64 V, V x 3 f64 positions,
//             u64 U, U x 2 f64 rest_uv, u64 T, T x 3 i32 triangles, u64 P, P x (u64 length, bytes) triangle places
//   status 1 or 2: u64 length, bytes of the message
// (native byte order: the child is a fork of this process.)
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/mesh_readers.h"

namespace tissu {
namespace {

using Clock = std::chrono::steady_clock;

enum : uint8_t { kRead = 0, kInputError = 1, kOtherError = 2 };

// --- encoding (in the child) ---

class Encoder {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  void put_string(const std::string& text) {
    put<uint64_t>(text.size());
    bytes_ += text;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

std::string encode(const MeshFileData& data) {
  Encoder out;
  out.put<uint8_t>(kRead);
  out.put<uint8_t>(data.mesh.uv_from_file ? 1 : 0);
  out.put<uint8_t>(data.mesh.file_vertex_ids ? 1 : 0);
  out.put<uint64_t>(data.mesh.positions.size());
  for (const Vec3& p : data.mesh.positions) {
    for (int k = 0; k < 3; ++k) out.put<double>(p[k]);
  }
  out.put<uint64_t>(data.mesh.rest_uv.size());
  for (const Vec2& uv : data.mesh.rest_uv) {
    for (int k = 0; k < 2; ++k) out.put<double>(uv[k]);
  }
  out.put<uint64_t>(data.mesh.triangles.size());
  for (const Tri& t : data.mesh.triangles) {
    for (int k = 0; k < 3; ++k) out.put<int32_t>(static_cast<int32_t>(t[k]));
  }
  out.put<uint64_t>(data.triangle_places.size());
  for (const std::string& place : data.triangle_places) out.put_string(place);
  return out.bytes();
}

std::string encode_error(uint8_t status, const std::string& message) {
  Encoder out;
  out.put<uint8_t>(status);
  out.put_string(message);
  return out.bytes();
}

// --- decoding (in the parent) ---

class Decoder {
 public:
  explicit Decoder(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    T value;
    if (bytes_.size() - at_ < sizeof value) throw std::length_error("truncated");
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  // A count of items of at least `item_size` bytes each that must fit in what is left.
  size_t get_count(size_t item_size) {
    const uint64_t n = get<uint64_t>();
    if (n > (bytes_.size() - at_) / item_size) throw std::length_error("bad count");
    return static_cast<size_t>(n);
  }
  std::string get_string() {
    const size_t n = get_count(1);
    std::string text = bytes_.substr(at_, n);
    at_ += n;
    return text;
  }
  bool at_end() const { return at_ == bytes_.size(); }

 private:
  const std::string& bytes_;
  size_t at_ = 0;
};

// --- the child ---

void write_all(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) _exit(3);  // the parent is gone or gave up: nothing to report to
    done += static_cast<size_t>(n);
  }
}

// Test hook (tests/mesh/isolated_read_test.cpp): TISSU_MESH_READ_TEST=hang|abort|segv makes
// the child hang, abort (after printing a line to stderr) or crash instead of reading. Only
// the child looks at it.
void run_test_hook() {
  const char* hook = std::getenv("TISSU_MESH_READ_TEST");
  if (!hook) return;
  if (std::strcmp(hook, "hang") == 0) {
    for (;;) pause();
  }
  if (std::strcmp(hook, "abort") == 0) {
    const char kLine[] = "Assertion failed (test hook)\n";  // as assimp's ai_assert prints
    const ssize_t ignored = write(STDERR_FILENO, kLine, sizeof kLine - 1);
    (void)ignored;
    std::abort();
  }
  if (std::strcmp(hook, "segv") == 0) raise(SIGSEGV);
}

[[noreturn]] void child_main(const std::string& path, bool texture, int fd, pid_t parent) {
#ifdef __linux__
  // Die with the parent (a parent killed while waiting must not leave a reader running).
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(3);
#else
  (void)parent;
#endif
  // A write to a pipe the parent has closed fails with EPIPE instead of killing the child;
  // SIGINT and SIGTERM (the parent's interrupt handlers) end the child.
  // A crash leaves no core file (a run on bad input leaves no output).
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  // Nothing the child prints reaches the user (assimp's failed assertions print a line
  // before they abort): the parent reports one line for it.
  const int null = open("/dev/null", O_RDWR | O_CLOEXEC);
  if (null >= 0) {
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    close(null);
  }
  signal(SIGPIPE, SIG_IGN);
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  std::string message;
  try {
    run_test_hook();
    message = encode(read_with_assimp_in_process(path, texture));
  } catch (const InputError& e) {
    message = encode_error(kInputError, e.what());
  } catch (const std::bad_alloc&) {
    message = encode_error(kOtherError, "out of memory");
  } catch (const std::exception& e) {
    message = encode_error(kOtherError, e.what());
  } catch (...) {
    message = encode_error(kOtherError, "unknown exception");
  }
  write_all(fd, message);
  close(fd);
  // No atexit handlers, static destructors or stdio flushes of the parent's state.
  _exit(0);
}

// --- the parent ---

std::string signal_name(int number) {
  const char* name = strsignal(number);
  return name ? name : "unknown signal";
}

// Kills and reaps the child (running or finished; only this code waits for it).
void kill_and_reap(pid_t child) {
  kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
}

}  // namespace

double mesh_read_timeout(unsigned long long bytes) {
  if (const char* text = std::getenv("TISSU_MESH_READ_TIMEOUT")) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end != text && *end == '\0' && std::isfinite(seconds) && seconds > 0) return seconds;
  }
  const unsigned long long mib = 1ull << 20;
  return 10.0 + static_cast<double>((bytes + mib - 1) / mib);
}

MeshFileData read_with_assimp(const std::string& path, bool texture) {
  auto fail = [&](const std::string& problem) { throw InputError(path + ": " + problem); };
  struct stat info {};
  const unsigned long long bytes =
      stat(path.c_str(), &info) == 0 ? static_cast<unsigned long long>(info.st_size) : 0;
  const double limit = mesh_read_timeout(bytes);

  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error(path + ": cannot start the mesh reader: pipe: " +
                             std::strerror(errno));
  }
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child < 0) {
    const int error = errno;
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error(path + ": cannot start the mesh reader: fork: " +
                             std::strerror(error));
  }
  if (child == 0) {
    close(fds[0]);
    child_main(path, texture, fds[1], parent);
  }
  close(fds[1]);
  const int fd = fds[0];

  // Read until end of file or the deadline.
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit));
  std::string received;
  bool timed_out = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(std::min<long long>(left.count() + 1, 1 << 30)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) break;  // treated as a reader that ended without a result
    if (ready == 0) continue;
    char chunk[65536];
    const ssize_t n = read(fd, chunk, sizeof chunk);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) break;  // end of file (the child closed the pipe or exited) or an error
    received.append(chunk, static_cast<size_t>(n));
  }
  close(fd);

  // Reap the child: it exits right after closing the pipe; wait for it until the deadline.
  int status = 0;
  bool reaped = false;
  while (!timed_out) {
    const pid_t r = waitpid(child, &status, WNOHANG);
    if (r == child) {
      reaped = true;
      break;
    }
    if (r < 0 && errno == ECHILD) {  // reaped already (SIGCHLD ignored): judge by the data
      reaped = true;
      break;
    }
    if (r < 0 && errno != EINTR) break;
    if (Clock::now() >= deadline) {
      timed_out = true;
      break;
    }
    const timespec pause_time{0, 1000000};  // 1 ms
    nanosleep(&pause_time, nullptr);
  }
  if (!reaped) kill_and_reap(child);
  if (timed_out) {
    fail("the mesh reader did not finish within " + format_short(limit) +
         " s (malformed file?)");
  }
  if (WIFSIGNALED(status)) {
    const int number = WTERMSIG(status);
    if (number == SIGINT || number == SIGTERM) {
      fail("the mesh reader was interrupted (signal " + std::to_string(number) + ": " +
           signal_name(number) + ")");
    }
    fail("the mesh reader crashed (signal " + std::to_string(number) + ": " +
         signal_name(number) + ") reading this file");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || received.empty()) {
    fail("the mesh reader ended without a result (exit status " +
         std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  }

  try {
    Decoder in(received);
    const uint8_t kind = in.get<uint8_t>();
    if (kind == kInputError) throw InputError(in.get_string());
    if (kind == kOtherError) fail("the mesh reader failed: " + in.get_string());
    if (kind != kRead) throw std::length_error("bad status");
    MeshFileData data;
    TriMesh& mesh = data.mesh;
    mesh.uv_from_file = in.get<uint8_t>() != 0;
    mesh.file_vertex_ids = in.get<uint8_t>() != 0;
    mesh.positions.resize(in.get_count(3 * sizeof(double)));
    for (Vec3& p : mesh.positions) {
      for (int k = 0; k < 3; ++k) p[k] = in.get<double>();
    }
    mesh.rest_uv.resize(in.get_count(2 * sizeof(double)));
    for (Vec2& uv : mesh.rest_uv) {
      for (int k = 0; k < 2; ++k) uv[k] = in.get<double>();
    }
    mesh.triangles.resize(in.get_count(3 * sizeof(int32_t)));
    for (Tri& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) t[k] = in.get<int32_t>();
    }
    data.triangle_places.resize(in.get_count(sizeof(uint64_t)));
    for (std::string& place : data.triangle_places) place = in.get_string();
    if (!in.at_end()) throw std::length_error("trailing bytes");
    return data;
  } catch (const std::length_error&) {
    fail("the mesh reader sent an incomplete result");
  }
  throw std::logic_error("unreachable");
}

}  // namespace tissu
