// tissu batch end to end with the local executor: grid expansion and job names, resume
// (skipping complete jobs, rerunning failed and interrupted ones), refusal of another
// batch in the same directory, failing jobs recorded while the others finish, summaries
// and the contact sheet.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <csignal>
#include <sys/wait.h>
#include <unistd.h>

#include "common/tissu_shell.h"
#include "video/png_io.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using tissu::test::read_text;

class Batch : public tissu::test::TempDirTest {
 protected:
  Batch() : TempDirTest("tissu_batch") {}

  void SetUp() override {
    TempDirTest::SetUp();
    // A small sheet falling for a few steps: 50 triangles, 64 x 48 pixels.
    std::ofstream(dir_ / "fall.json") << R"({
      "name": "fall", "dt": 0.004, "duration": 0.1, "integrator": "backward_euler",
      "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                         "irregular": true, "seed": 3},
                "material": "silk"},
      "gravity": [0, 0, -9.81],
      "render": {"width": 64, "height": 48, "msaa": 1, "fps": 30}
    })";
  }

  std::string write_batch(const std::string& name, Json batch) {
    if (!batch.contains("scene") && !batch.contains("scenes") && !batch.contains("figures") &&
        !batch.contains("experiments")) {
      batch["scene"] = "fall.json";
    }
    const fs::path path = dir_ / name;
    std::ofstream(path) << batch.dump(2);
    return path.string();
  }

  tissu::test::ShellResult run(const std::string& args) {
    return tissu::test::run_tissu_shell(args, dir_ / "stderr.txt", true);
  }

  tissu::test::ShellResult batch(const std::string& file, const fs::path& out) {
    return run("batch " + file + " --out " + out.string() + " --jobs 2");
  }

  static Json read_json(const fs::path& p) {
    std::ifstream in(p);
    return Json::parse(in);
  }

  static std::vector<std::string> job_names(const fs::path& out) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(out / "jobs")) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  static std::vector<std::string> lines_of(const fs::path& p) {
    std::vector<std::string> lines;
    std::istringstream in(read_text(p));
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
};

TEST_F(Batch, GridGivesOneJobPerCombinationNamedFromItsOverrides) {
  const std::string file = write_batch(
      "grid.json", {{"produce", "run"},
                    {"grid", {{"cloth.material", {"silk", "cotton"}}, {"dt", {0.004, 0.002}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(job_names(out), (std::vector<std::string>{"material-cotton_dt-0.002", "material-cotton_dt-0.004",
                                                      "material-silk_dt-0.002", "material-silk_dt-0.004"}));
  const Json report = read_json(out / "jobs" / "material-cotton_dt-0.002" / "report.json");
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["dt"], 0.002);
  EXPECT_EQ(report["overrides"], Json({"cloth.material=cotton", "dt=0.002"}));
  EXPECT_EQ(read_json(out / "jobs" / "material-silk_dt-0.004" / "state.json")["status"], "done");
  EXPECT_EQ(read_json(out / "batch.json")["jobs"].size(), 4u);
}

TEST_F(Batch, ListOfScenesNamesJobsAfterTheFiles) {
  fs::copy_file(dir_ / "fall.json", dir_ / "drop.json");
  const std::string file =
      write_batch("scenes.json", {{"produce", "run"}, {"scenes", {"fall.json", "drop.json"}}, {"set", {{"dt", 0.002}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(job_names(out), (std::vector<std::string>{"drop", "fall"}));
  EXPECT_EQ(read_json(out / "jobs" / "drop" / "report.json")["dt"], 0.002);
}

TEST_F(Batch, RerunSkipsCompleteJobs) {
  const std::string file =
      write_batch("b.json", {{"produce", "run"}, {"grid", {{"cloth.material", {"silk", "cotton"}}}}});
  const fs::path out = dir_ / "out";
  ASSERT_EQ(batch(file, out).exit_code, 0);
  const std::string state = read_text(out / "jobs" / "material-silk" / "state.json");
  const std::string report = read_text(out / "jobs" / "material-silk" / "report.json");
  const auto again = batch(file, out);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("2 complete (skipped), 0 to run"), std::string::npos) << again.err;
  EXPECT_EQ(read_text(out / "jobs" / "material-silk" / "state.json"), state);
  EXPECT_EQ(read_text(out / "jobs" / "material-silk" / "report.json"), report);
}

TEST_F(Batch, FailingJobIsRecordedWhileTheOthersFinish) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"},
                 {"list", {{{"cloth.material", "silk"}}, {{"cloth.material", "velvet"}}, {{"cloth.material", "linen"}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("job material-velvet: "), std::string::npos) << r.err;
  const Json failed = read_json(out / "jobs" / "material-velvet" / "state.json");
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(failed["exit_code"], 2);
  EXPECT_NE(failed["error"].get<std::string>().find("velvet"), std::string::npos) << failed;
  EXPECT_EQ(read_json(out / "jobs" / "material-silk" / "state.json")["status"], "done");
  EXPECT_EQ(read_json(out / "jobs" / "material-linen" / "state.json")["status"], "done");
  EXPECT_EQ(read_json(out / "jobs" / "material-linen" / "report.json")["status"], "ok");
}

TEST_F(Batch, DivergingJobIsRecordedAsFailed) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"},
                 {"list", {{{"integrator", "backward_euler"}},
                           {{"integrator", "explicit_euler"}, {"cloth.transform.scale", 1.05}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  // (The test's JSON objects keep their keys in alphabetical order.)
  const Json failed = read_json(out / "jobs" / "scale-1.05_integrator-explicit_euler" / "state.json");
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(failed["exit_code"], 3);
  EXPECT_NE(failed["error"].get<std::string>().find("diverged at step"), std::string::npos) << failed;
  EXPECT_EQ(read_json(out / "jobs" / "integrator-backward_euler" / "state.json")["status"], "done");
}

TEST_F(Batch, RerunRunsFailedAndInterruptedJobsOnly) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"},
                 {"list", {{{"cloth.material", "silk"}}, {{"cloth.material", "velvet"}}, {{"cloth.material", "linen"}}}}});
  const fs::path out = dir_ / "out";
  ASSERT_EQ(batch(file, out).exit_code, 1);
  // linen as a run killed half-way leaves it: state "running", no report.
  Json state = read_json(out / "jobs" / "material-linen" / "state.json");
  state["status"] = "running";
  std::ofstream(out / "jobs" / "material-linen" / "state.json") << state.dump();
  fs::remove(out / "jobs" / "material-linen" / "report.json");
  const std::string silk_state = read_text(out / "jobs" / "material-silk" / "state.json");

  const auto again = batch(file, out);
  EXPECT_EQ(again.exit_code, 1) << again.err;
  EXPECT_NE(again.err.find("1 complete (skipped), 2 to run"), std::string::npos) << again.err;
  EXPECT_EQ(read_text(out / "jobs" / "material-silk" / "state.json"), silk_state);
  EXPECT_EQ(read_json(out / "jobs" / "material-linen" / "state.json")["status"], "done");
  EXPECT_EQ(read_json(out / "jobs" / "material-linen" / "report.json")["status"], "ok");
  EXPECT_EQ(read_json(out / "jobs" / "material-velvet" / "state.json")["status"], "failed");
}

TEST_F(Batch, AnotherBatchInTheSameDirectoryIsRefused) {
  const fs::path out = dir_ / "out";
  const std::string first =
      write_batch("a.json", {{"produce", "run"}, {"grid", {{"cloth.material", {"silk"}}}}});
  ASSERT_EQ(batch(first, out).exit_code, 0);
  const std::string plan = read_text(out / "batch.json");
  const std::string second =
      write_batch("b.json", {{"produce", "run"}, {"grid", {{"cloth.material", {"cotton"}}}}});
  const auto r = batch(second, out);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("holds the outputs of another batch"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(read_text(out / "batch.json"), plan);
  EXPECT_EQ(job_names(out), std::vector<std::string>{"material-silk"});

  // Nor is a directory that holds something else.
  fs::create_directories(dir_ / "other");
  std::ofstream(dir_ / "other" / "notes.txt") << "mine\n";
  const auto other = batch(first, dir_ / "other");
  EXPECT_EQ(other.exit_code, 2) << other.err;
  EXPECT_NE(other.err.find("not a batch directory"), std::string::npos) << other.err;
  EXPECT_FALSE(fs::exists(dir_ / "other" / "jobs"));
}

TEST_F(Batch, BadBatchFilesGiveOneLineAndWriteNothing) {
  struct Case {
    Json batch;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{{"grdi", {{"dt", {0.001}}}}}, "b.json: grdi: unknown key"},
      {{{"grid", {{"dt", 0.001}}}}, "b.json: grid.dt: expected a non-empty list of values"},
      {{{"produce", "film"}}, "b.json: produce: unknown value \"film\""},
      {{{"scenes", {"fall.json"}}, {"grid", {{"dt", {0.001}}}}}, "b.json: grid: a list of \"scenes\" takes no grid"},
      {{{"scene", "fall.json"}, {"scenes", {"fall.json"}}}, "b.json: scenes: give either"},
      {{{"grid", {{"dt", {0.001}}}}, {"list", {Json::object()}}}, "b.json: list: give either"},
      {{{"list", {1, 2}}}, "b.json: list[0]: expected an object"},
      {{{"options", {"--check", "--out"}}}, "b.json: options[1]: --out is set by the batch itself"},
  };
  for (const Case& c : cases) {
    const std::string file = write_batch("b.json", c.batch);
    const auto r = batch(file, dir_ / "out");
    EXPECT_EQ(r.exit_code, 2) << c.batch;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << c.batch;
  }
  std::ofstream(dir_ / "syntax.json") << "{\"grid\": {\n  \"dt\": [0.1,]\n}}";
  const auto r = batch((dir_ / "syntax.json").string(), dir_ / "out");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("syntax.json:2:"), std::string::npos) << r.err;
  const auto missing = batch((dir_ / "none.json").string(), dir_ / "out");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.json: cannot open batch file"), std::string::npos) << missing.err;
}

TEST_F(Batch, SummariesHaveOneRowPerJob) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"},
                 {"list", {{{"cloth.material", "silk"}}, {{"cloth.material", "velvet"}}}}});
  const fs::path out = dir_ / "out";
  batch(file, out);
  const std::vector<std::string> csv = lines_of(out / "summary.csv");
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[0].rfind("job,cloth.material,status,exit_code,started,finished,wall_s,steps_done,", 0), 0u) << csv[0];
  EXPECT_EQ(csv[1].rfind("material-silk,silk,done,0,", 0), 0u) << csv[1];
  EXPECT_NE(csv[1].find(",25,"), std::string::npos) << csv[1];  // steps done
  EXPECT_EQ(csv[2].rfind("material-velvet,velvet,failed,2,", 0), 0u) << csv[2];
  EXPECT_NE(csv[2].find("velvet"), std::string::npos);
  const std::string md = read_text(out / "summary.md");
  EXPECT_NE(md.find("| job | cloth.material | status |"), std::string::npos) << md;
  EXPECT_NE(md.find("| material-silk | silk | done | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("1 done, 1 failed"), std::string::npos) << md;
  // The gathering step alone writes the same rows again.
  fs::remove(out / "summary.csv");
  const auto gathered = run("batch gather " + out.string());
  EXPECT_EQ(gathered.exit_code, 0) << gathered.err;
  EXPECT_EQ(lines_of(out / "summary.csv"), csv);
}

TEST_F(Batch, ContactSheetShowsEveryJobsStills) {
  const std::string file = write_batch(
      "b.json", {{"produce", "stills"}, {"stills", 2}, {"grid", {{"cloth.material", {"silk", "cotton"}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / "jobs" / "material-silk" / "fall.mp4"));
  const tissu::Image sheet = tissu::read_png((out / "contact_sheet.png").string());
  // Two columns (the stills of a job) of 64 x 48 panels with 11-pixel margins, one row
  // per job with its caption, and the title.
  EXPECT_EQ(sheet.width, 2 * 11 + 2 * 64 + 11 + 1);
  EXPECT_GT(sheet.height, 2 * 11 + 2 * 48 + 11);
  EXPECT_LT(sheet.height, 2 * 11 + 2 * 48 + 11 + 2 * 40 + 40);
}

TEST_F(Batch, RenderJobsWriteVideoAndStills) {
  const std::string file = write_batch("b.json", {{"stills", 1}, {"list", {{{"dt", 0.002}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "jobs" / "dt-0.002" / "fall.mp4"));
  EXPECT_TRUE(fs::exists(out / "contact_sheet.png"));
  // A missing video makes the job incomplete: the rerun renders it again.
  fs::remove(out / "jobs" / "dt-0.002" / "fall.mp4");
  const auto again = batch(file, out);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("0 complete (skipped), 1 to run"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(out / "jobs" / "dt-0.002" / "fall.mp4"));
}

TEST_F(Batch, FiguresAreJobsToo) {
  for (const char* name : {"one", "two"}) {
    std::ofstream(dir_ / (std::string(name) + ".json")) << R"({
      "title": "A small figure", "columns": 1, "panel_size": [64, 48],
      "panels": [{"scene": "fall.json", "step": 5, "caption": "{name}"}]
    })";
  }
  const std::string file = write_batch("b.json", {{"figures", {"one.json", "two.json"}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(job_names(out), (std::vector<std::string>{"one", "two"}));
  const tissu::Image figure = tissu::read_png((out / "jobs" / "one" / "figure.png").string());
  EXPECT_GT(figure.width, 64);
  EXPECT_TRUE(fs::exists(out / "jobs" / "two" / "figure.report.json"));
  const tissu::Image sheet = tissu::read_png((out / "contact_sheet.png").string());
  EXPECT_GT(sheet.width, 2 * figure.width);  // the two figures side by side
  const auto again = batch(file, out);
  EXPECT_NE(again.err.find("2 complete (skipped), 0 to run"), std::string::npos) << again.err;

  const std::string mixed = write_batch("m.json", {{"figures", {"one.json"}}, {"stills", 2}});
  const auto refused = batch(mixed, dir_ / "mixed");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("m.json: stills: a list of \"figures\" takes no \"stills\""), std::string::npos)
      << refused.err;
}

// Also: a second run of the batch in the same directory is refused while the first runs.
TEST_F(Batch, InterruptStopsTheRunningJobsAndStartsNoMore) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"},
                 {"set", {{"steps", 100000000}, {"gravity", {0, 0, 0}}}},  // at rest for ever
                 {"list", {{{"cloth.material", "silk"}}, {{"cloth.material", "linen"}}}}});
  const fs::path out = dir_ / "out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out_arg = out.string();
    execl(TISSU_BINARY, TISSU_BINARY, "batch", file.c_str(), "--out", out_arg.c_str(), "--jobs", "1",
          "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the first job runs, then interrupt the batch.
  const fs::path state = out / "jobs" / "material-silk" / "state.json";
  for (int i = 0; i < 600 && read_text(state).find("running") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // Meanwhile, the same batch in the same directory is refused.
  const auto second = batch(file, out);
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_NE(second.err.find("another tissu batch runs in this directory (process " + std::to_string(pid) + ")"),
            std::string::npos)
      << second.err;
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(read_json(state)["status"], "interrupted");
  // The job writes its report when the signal came after it had started simulating (a
  // job still loading its scene dies of the signal).
  const fs::path report = out / "jobs" / "material-silk" / "report.json";
  if (fs::exists(report)) {
    EXPECT_EQ(read_json(report)["status"], "interrupted");
  }
  EXPECT_FALSE(fs::exists(out / "jobs" / "material-linen" / "state.json"));  // never started
  const std::vector<std::string> csv = lines_of(out / "summary.csv");
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[1].rfind("material-silk,", 0), 0u);
  EXPECT_NE(csv[1].find(",interrupted,130,"), std::string::npos) << csv[1];
  EXPECT_NE(csv[2].find(",pending,"), std::string::npos) << csv[2];
}

TEST_F(Batch, StudiesAreJobsWithTheirOptions) {
  const std::string file = write_batch(
      "b.json", {{"produce", "study"},
                 {"options", {"--integrators", "backward_euler", "--dts", "0.004,0.008", "--ref-dt", "1e-4"}},
                 {"grid", {{"cloth.material", {"silk", "cotton"}}}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(out / "jobs" / "material-cotton" / "study.csv");
  EXPECT_NE(csv.find("backward_euler"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("bdf2"), std::string::npos) << csv;  // --integrators reached the study
  EXPECT_TRUE(fs::exists(out / "jobs" / "material-silk" / "study.png"));
  EXPECT_TRUE(fs::exists(out / "contact_sheet.png"));
  const auto again = batch(file, out);
  EXPECT_NE(again.err.find("2 complete (skipped), 0 to run"), std::string::npos) << again.err;
}

// The paper's experiments, one job each: each writes the results of its own experiment.
TEST_F(Batch, PaperExperimentsAreJobs) {
  const std::string file = write_batch(
      "b.json", {{"experiments", {"hung", "timing"}},
                 {"paper_scenes", std::string(TISSU_SOURCE_DIR) + "/scenes/paper"},
                 {"options", {"--quick"}}});
  const fs::path out = dir_ / "out";
  const auto r = batch(file, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string hung = read_text(out / "jobs" / "hung" / "paper-results.md");
  const std::string timing = read_text(out / "jobs" / "timing" / "paper-results.md");
  EXPECT_NE(hung.find("--experiments hung"), std::string::npos) << hung;
  EXPECT_NE(timing.find("--experiments timing"), std::string::npos) << timing;
  EXPECT_NE(hung, timing);
  EXPECT_TRUE(fs::exists(out / "jobs" / "timing" / "paper-results.csv"));
  EXPECT_NE(read_text(out / "summary.csv").find("hung"), std::string::npos);
  const auto again = batch(file, out);
  EXPECT_NE(again.err.find("2 complete (skipped), 0 to run"), std::string::npos) << again.err;
  // A name that is not one of the experiments is refused in one line.
  const std::string bad = write_batch("bad.json", {{"experiments", {"timing", "speed"}}});
  const auto refused = batch(bad, dir_ / "bad");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("experiments[1]: expected one of timing, divergence, accuracy, hung"),
            std::string::npos) << refused.err;
}

TEST_F(Batch, StatusListsEveryJob) {
  const std::string file = write_batch(
      "b.json", {{"produce", "run"}, {"list", {{{"cloth.material", "silk"}}, {{"cloth.material", "velvet"}}}}});
  const fs::path out = dir_ / "out";
  batch(file, out);
  const fs::path listing = dir_ / "status.txt";
  const int status = std::system((std::string(TISSU_BINARY) + " batch status " + out.string() + " > " +
                                  listing.string() + " 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const std::string text = read_text(listing);
  EXPECT_NE(text.find("material-silk  done"), std::string::npos) << text;
  EXPECT_NE(text.find("material-velvet  failed"), std::string::npos) << text;
  EXPECT_NE(text.find("1 done, 1 failed"), std::string::npos) << text;
}

}  // namespace
