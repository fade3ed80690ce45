// For tests that run the tissu binary (TISSU_BINARY, a compile definition of the test
// target) through the shell, each in a fresh directory of its own.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace tissu::test {

namespace fs = std::filesystem;

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct ShellResult {
  int exit_code;    // -1 when tissu did not exit normally
  std::string err;  // its stderr
};

// Runs "tissu ARGS" through the shell with stderr into err_file (and stdout discarded
// when asked).
inline ShellResult run_tissu_shell(const std::string& args, const fs::path& err_file,
                                   bool discard_stdout = false) {
  const std::string command = std::string(TISSU_BINARY) + " " + args +
                              (discard_stdout ? " > /dev/null" : "") + " 2>" + err_file.string();
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(err_file)};
}

// A fixture with a fresh directory dir_ per test: <tmp>/<prefix>_<pid>_<test name>,
// removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           (prefix_ + "_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;

 private:
  std::string prefix_;
};

}  // namespace tissu::test
