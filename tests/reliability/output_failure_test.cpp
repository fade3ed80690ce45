// Output that cannot be written: directories that cannot be created, a full disk (simulated
// with RLIMIT_FSIZE: every write past the limit fails with EFBIG, as ENOSPC would), output
// paths that are devices, named pipes, directories or symlinks. The run exits non-zero with one line naming the file, and
// no report or snapshot is left truncated or half-written.
#include "tissu_process.h"

#include <sys/stat.h>
#include <sys/sysmacros.h>

namespace tissu::reliability {
namespace {

class OutputFailure : public TissuProcess {
 protected:
  std::string scene() { return write("scene.json", small_scene().dump(2)); }

  // Files under `dir` (relative to the work directory), recursively.
  std::vector<std::string> files_under(const std::string& dir) const {
    std::vector<std::string> out;
    if (!fs::exists(work_ / dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(work_ / dir)) {
      if (!e.is_directory()) out.push_back(fs::relative(e.path(), work_).string());
    }
    return out;
  }
};

// An output problem, exit code 1 (README), in one line naming the directory.
TEST_F(OutputFailure, OutputDirectoryThatCannotBeCreated) {
  write("file", "x");
  const Outcome o = run({"run", scene(), "--out", "file/sub", "--quiet"});
  EXPECT_EQ(o.exit_code, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_EQ(o.err.rfind("tissu: file/sub: cannot create output directory: ", 0), 0u) << o.err;
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
}

// --out is created first; when the report's directory then cannot be created, the run
// removes the (still empty) directories it created itself.
TEST_F(OutputFailure, ReportDirectoryThatCannotBeCreatedLeavesNoOutputDirectory) {
  write("file", "x");
  const Outcome o = run({"run", scene(), "--out", "out", "--report", "file/r.json", "--quiet"});
  EXPECT_EQ(o.exit_code, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_EQ(o.err.rfind("tissu: file: ", 0), 0u) << o.err;
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
}

TEST_F(OutputFailure, FullDiskWhileWritingTheReport) {
  const Outcome o = run({"run", scene(), "--out", "out", "--quiet"}, Limits{1024});
  EXPECT_EQ(o.exit_code, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_NE(o.err.find("tissu: out/report.json: cannot write: File too large"), std::string::npos)
      << o.err;
  EXPECT_TRUE(files_under("out").empty()) << "left " << files_under("out").front();
}

TEST_F(OutputFailure, FullDiskWhileWritingAnObjSnapshot) {
  const Outcome o = run({"run", scene(), "--out", "out", "--obj-every", "10", "--quiet"},
                        Limits{1024});
  EXPECT_NE(o.exit_code, 0);
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_NE(o.err.find("tissu: out/obj/frame_000000.obj: cannot write: File too large"),
            std::string::npos)
      << o.err;
  EXPECT_TRUE(files_under("out").empty()) << "left " << files_under("out").front();
}

// Checks the output-error contract for a refused output path: exit code 1, one line
// "tissu: <path>: cannot write: not a regular file (<kind>)".
#define EXPECT_REFUSED(outcome, path, kind)                                                 \
  do {                                                                                      \
    const ::tissu::reliability::Outcome& o_ = (outcome);                                    \
    EXPECT_EQ(o_.exit_code, 1) << o_.err;                                                   \
    EXPECT_EQ(o_.lines(), 1) << "stderr must be one line:\n" << o_.err;                     \
    EXPECT_EQ(o_.err, "tissu: " + std::string(path) +                                      \
                          ": cannot write: not a regular file (" kind ")\n");               \
  } while (0)

bool is_char_device(const fs::path& p) {
  struct stat info {};
  return lstat(p.c_str(), &info) == 0 && S_ISCHR(info.st_mode);
}

// Files are written under a temporary name and renamed into place, and the rename would
// replace a symbolic link at the final path: such a link is refused and left as it is, and
// its target is never written through (so /dev/full, or any file a link points to, is left
// alone).
TEST_F(OutputFailure, SymlinksAreRefusedNeitherReplacedNorWrittenThrough) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_directories(work_ / "out" / "obj");
  write("elsewhere.json", "keep");
  fs::create_symlink(work_ / "elsewhere.json", work_ / "out" / "report.json");
  Outcome o = run({"run", scene(), "--out", "out", "--quiet"});
  EXPECT_REFUSED(o, "out/report.json", "symbolic link to a regular file");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  EXPECT_TRUE(fs::is_symlink(work_ / "out" / "report.json"));
  std::ifstream kept(work_ / "elsewhere.json");
  std::string text;
  kept >> text;
  EXPECT_EQ(text, "keep") << "the link's target must not be written";

  fs::remove(work_ / "out" / "report.json");
  fs::create_symlink("/dev/full", work_ / "out" / "report.json");
  o = run({"run", scene(), "--out", "out", "--quiet"});
  EXPECT_REFUSED(o, "out/report.json", "symbolic link to a character device");
  EXPECT_TRUE(fs::is_symlink(work_ / "out" / "report.json"));
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();

  // An earlier run's snapshot is checked before the run, with or without --overwrite
  // (which would otherwise remove it).
  fs::create_symlink("/dev/full", work_ / "out" / "obj" / "final.obj");
  for (const char* overwrite : {"--quiet", "--overwrite"}) {
    o = run({"run", scene(), "--out", "out", "--report", "r.json", "--obj-every", "1000",
             "--quiet", overwrite});
    EXPECT_REFUSED(o, "out/obj/final.obj", "symbolic link to a character device");
    EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  }
  EXPECT_TRUE(fs::is_symlink(work_ / "out" / "obj" / "final.obj"));
  EXPECT_TRUE(is_char_device("/dev/full")) << "/dev/full must still be the device";
}

// An output path that is a device (`--report /dev/full`), a named pipe, a directory or a link
// to a device (/dev/stdout) is refused before the run, with exit code 1 and one line, and
// never replaced: as root, renaming the finished report onto /dev/full used to put a
// regular file in place of the device node.
TEST_F(OutputFailure, ReportOnADeviceIsRefusedAndTheDeviceKept) {
  // First on a device node of our own (as root; the same device as /dev/full), so that a
  // regression replaces that node and stops the test before /dev/full is at stake.
  if (geteuid() == 0) {
    ASSERT_EQ(mknod(path("full").c_str(), S_IFCHR | 0666, makedev(1, 7)), 0);
    const Outcome o = run({"run", scene(), "--out", "out", "--report", "full", "--quiet"});
    EXPECT_REFUSED(o, "full", "character device");
    EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
    ASSERT_TRUE(is_char_device(work_ / "full")) << "the device node was replaced";
  }
  ASSERT_FALSE(HasFailure());
  if (!is_char_device("/dev/full")) GTEST_SKIP() << "no /dev/full device";
  Outcome o = run({"run", scene(), "--out", "out", "--report", "/dev/full", "--quiet"});
  EXPECT_REFUSED(o, "/dev/full", "character device");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  EXPECT_TRUE(is_char_device("/dev/full")) << "/dev/full must still be the device";
  EXPECT_FALSE(fs::exists(fs::symlink_status("/dev/.full.partial")));

  // /dev/stdout is a link to the process's standard output, here /dev/null.
  if (fs::is_symlink("/dev/stdout")) {
    o = run({"run", scene(), "--out", "out", "--report", "/dev/stdout", "--quiet"});
    EXPECT_REFUSED(o, "/dev/stdout", "symbolic link to a character device");
    EXPECT_TRUE(fs::is_symlink("/dev/stdout")) << "/dev/stdout must still be a link";
    EXPECT_FALSE(fs::exists(fs::symlink_status("/dev/.stdout.partial")));
  }
}

TEST_F(OutputFailure, OutputPathsThatAreNotRegularFilesAreRefused) {
  fs::create_directories(work_ / "out" / "obj");
  ASSERT_EQ(mkfifo(path("out/report.json").c_str(), 0644), 0);
  Outcome o = run({"run", scene(), "--out", "out", "--quiet"});
  EXPECT_REFUSED(o, "out/report.json", "named pipe");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  EXPECT_TRUE(fs::is_fifo(work_ / "out" / "report.json"));

  fs::create_directories(work_ / "report.json");
  o = run({"run", scene(), "--out", "out", "--report", "report.json", "--quiet"});
  EXPECT_REFUSED(o, "report.json", "directory");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();

  // The video, refused before the renderer starts.
  ASSERT_EQ(mkfifo(path("out/small.mp4").c_str(), 0644), 0);
  o = run({"render", scene(), "--out", "out", "--report", "r.json", "--quiet"});
  EXPECT_REFUSED(o, "out/small.mp4", "named pipe");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  EXPECT_TRUE(fs::is_fifo(work_ / "out" / "small.mp4"));

  // An earlier run's snapshot, refused before the run.
  ASSERT_EQ(mkfifo(path("out/obj/frame_000000.obj").c_str(), 0644), 0);
  o = run({"run", scene(), "--out", "out", "--report", "r.json", "--obj-every", "10", "--quiet"});
  EXPECT_REFUSED(o, "out/obj/frame_000000.obj", "named pipe");
  EXPECT_TRUE(o.created.empty()) << "created " << o.created.front();
  EXPECT_TRUE(fs::is_fifo(work_ / "out" / "obj" / "frame_000000.obj"));
}

}  // namespace
}  // namespace tissu::reliability
