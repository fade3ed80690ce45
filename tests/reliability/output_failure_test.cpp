// Output that cannot be written: directories that cannot be created, a full disk (simulated
// with RLIMIT_FSIZE: every write past the limit fails with EFBIG, as ENOSPC would), files
// that are symlinks to /dev/full. The run exits non-zero with one line naming the file, and
// no report or snapshot is left truncated or half-written.
#include "tissu_process.h"

#include <sys/stat.h>

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

TEST_F(OutputFailure, OutputDirectoryThatCannotBeCreated) {
  write("file", "x");
  const Outcome o = run({"run", scene(), "--out", "file/sub", "--quiet"});
  EXPECT_BAD_INPUT(o, "file/sub: cannot create output directory");
}

// --out is created first; when the report's directory then cannot be created, the run
// removes the (still empty) directories it created itself.
TEST_F(OutputFailure, ReportDirectoryThatCannotBeCreatedLeavesNoOutputDirectory) {
  write("file", "x");
  const Outcome o = run({"run", scene(), "--out", "out", "--report", "file/r.json", "--quiet"});
  EXPECT_BAD_INPUT(o, "file: ");
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
  EXPECT_NE(o.err.find("tissu: out/obj/frame_000000.obj: write failed: File too large"),
            std::string::npos)
      << o.err;
  EXPECT_TRUE(files_under("out").empty()) << "left " << files_under("out").front();
}

// Files are written under a temporary name and renamed into place: a symlink at the
// report's or a snapshot's path is replaced by the finished file, never written through
// (so /dev/full, or any file the link points to, is left alone).
TEST_F(OutputFailure, SymlinksToDevFullAreReplacedNotWrittenThrough) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_directories(work_ / "out" / "obj");
  fs::create_symlink("/dev/full", work_ / "out" / "report.json");
  fs::create_symlink("/dev/full", work_ / "out" / "obj" / "final.obj");
  const Outcome o = run({"run", scene(), "--out", "out", "--obj-every", "1000", "--quiet"});
  EXPECT_EQ(o.exit_code, 0) << o.err;
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(work_ / "out" / "report.json")));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(work_ / "out" / "obj" / "final.obj")));
  std::ifstream in(work_ / "out" / "report.json");
  EXPECT_EQ(Json::parse(in)["status"], "ok");
  struct stat info {};
  ASSERT_EQ(stat("/dev/full", &info), 0);
  EXPECT_TRUE(S_ISCHR(info.st_mode)) << "/dev/full must still be the device";
}

}  // namespace
}  // namespace tissu::reliability
