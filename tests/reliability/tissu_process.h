// Runs the real tissu binary in a temporary directory and captures what it leaves behind:
// exit code, stderr, and the files and directories it created.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace tissu::reliability {

namespace fs = std::filesystem;
using Json = nlohmann::json;

struct Outcome {
  int exit_code = -1;     // -1 when killed by a signal
  int signal = 0;
  std::string err;        // stderr
  std::vector<std::string> created;  // paths (relative to the work directory) that are new

  int lines() const { return static_cast<int>(std::count(err.begin(), err.end(), '\n')); }
};

// What a child process should face besides its arguments.
struct Limits {
  long long max_file_bytes = -1;  // RLIMIT_FSIZE: larger writes fail with EFBIG (a full disk)
};

class TissuProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "tissu-reliability-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    root_ = pattern;
    work_ = root_ / "work";
    fs::create_directories(work_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }

  // A file in the work directory.
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = work_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string path(const std::string& name) const { return (work_ / name).string(); }

  std::set<std::string> listing() const {
    std::set<std::string> out;
    for (auto it = fs::recursive_directory_iterator(work_); it != fs::recursive_directory_iterator();
         ++it) {
      out.insert(fs::relative(it->path(), work_).string());
    }
    return out;
  }

  // Starts tissu with `args` in the work directory (so the default out/ would land there)
  // and returns at once; `finish` waits for it and collects the outcome.
  struct Child {
    pid_t pid = -1;
    std::set<std::string> before;  // the work directory's listing before the start
  };
  Child start(const std::vector<std::string>& args, const Limits& limits = {}) {
    Child child;
    child.before = listing();
    const std::string err_file = (root_ / "stderr.txt").string();
    child.pid = fork();
    if (child.pid == 0) {
      if (chdir(work_.c_str()) != 0) _exit(126);
      const int fd = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd < 0 || dup2(fd, STDERR_FILENO) < 0) _exit(126);
      const int null = open("/dev/null", O_WRONLY);
      if (null >= 0) dup2(null, STDOUT_FILENO);
      // Sanitizer builds: third-party leaks only (tests/lsan.supp), never the project's.
      setenv("LSAN_OPTIONS", "suppressions=" TISSU_SOURCE_DIR "/tests/lsan.supp", 1);
      if (limits.max_file_bytes >= 0) {
        signal(SIGXFSZ, SIG_IGN);  // stays ignored across exec: writes fail with EFBIG
        const rlimit limit{static_cast<rlim_t>(limits.max_file_bytes),
                           static_cast<rlim_t>(limits.max_file_bytes)};
        setrlimit(RLIMIT_FSIZE, &limit);
      }
      std::vector<char*> argv{const_cast<char*>(TISSU_BINARY)};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(TISSU_BINARY, argv.data());
      _exit(127);
    }
    return child;
  }

  Outcome finish(const Child& child) {
    Outcome out;
    int status = 0;
    waitpid(child.pid, &status, 0);
    if (WIFEXITED(status)) out.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) out.signal = WTERMSIG(status);
    std::ifstream in(root_ / "stderr.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    out.err = ss.str();
    for (const std::string& p : listing()) {
      if (!child.before.count(p)) out.created.push_back(p);
    }
    return out;
  }

  // Runs tissu with `args` in the work directory and waits for it.
  Outcome run(const std::vector<std::string>& args, const Limits& limits = {}) {
    return finish(start(args, limits));
  }

  // A scene that runs quickly: a small rectangle of cotton, a few steps.
  static Json small_scene() {
    return Json::parse(R"({
      "name": "small", "dt": 1e-4, "steps": 20, "integrator": "symplectic_euler",
      "cloth": {"mesh": {"generate": "rectangle", "size": [0.4, 0.3], "triangles": 100,
                         "irregular": false},
                "material": "cotton"},
      "gravity": [0, 0, -9.81]
    })");
  }

  fs::path root_;
  fs::path work_;
};

// Checks the bad-input contract: exit code 2, exactly one line on stderr that starts with
// "tissu: " and contains every piece of `expected` (file, place, problem), nothing created.
#define EXPECT_BAD_INPUT(outcome, ...)                                                      \
  do {                                                                                      \
    const ::tissu::reliability::Outcome& o_ = (outcome);                                    \
    EXPECT_EQ(o_.exit_code, 2) << o_.err;                                                   \
    EXPECT_EQ(o_.lines(), 1) << "stderr must be one line:\n" << o_.err;                     \
    EXPECT_EQ(o_.err.rfind("tissu: ", 0), 0u) << o_.err;                                    \
    for (const std::string& piece_ : std::vector<std::string>{__VA_ARGS__}) {               \
      EXPECT_NE(o_.err.find(piece_), std::string::npos)                                     \
          << "stderr lacks \"" << piece_ << "\":\n" << o_.err;                              \
    }                                                                                       \
    EXPECT_TRUE(o_.created.empty()) << "created " << o_.created.size() << " paths, first "  \
                                    << (o_.created.empty() ? "" : o_.created.front());      \
  } while (0)

}  // namespace tissu::reliability
