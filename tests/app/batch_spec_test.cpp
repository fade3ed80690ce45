// Batch files read into jobs: names from overrides, unique names, --set texts; and the
// helpers of the slurm executor and the summaries.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "app/batch_gather.h"
#include "app/batch_slurm.h"
#include "app/batch_spec.h"
#include "study/output.h"

namespace {

namespace fs = std::filesystem;
using tissu::BatchSpec;

class BatchSpecTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tissu_batch_spec_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  BatchSpec read(const std::string& text) {
    const fs::path file = dir_ / "b.json";
    std::ofstream(file) << text;
    return tissu::read_batch_file(file.string());
  }

  static std::vector<std::string> names(const BatchSpec& b) {
    std::vector<std::string> out;
    for (const auto& j : b.jobs) out.push_back(j.name);
    return out;
  }

  fs::path dir_;
};

TEST_F(BatchSpecTest, GridKeysVaryInTheOrderWrittenFirstSlowest) {
  const BatchSpec b = read(R"({"scene": "s.json", // comments as in scene files
                               "grid": {"dt": [1e-3, 2e-3], "cloth.material": ["silk", "linen"]}})");
  EXPECT_EQ(names(b), (std::vector<std::string>{"dt-0.001_material-silk", "dt-0.001_material-linen",
                                                "dt-0.002_material-silk", "dt-0.002_material-linen"}));
  EXPECT_EQ(b.jobs[1].overrides[1].assignment(), "cloth.material=linen");
  EXPECT_EQ(b.jobs[0].scene_file, (dir_ / "s.json").lexically_normal().string());
}

TEST_F(BatchSpecTest, KeysEndingAlikeAreNamedInFullAndEqualNamesNumbered) {
  const BatchSpec b = read(R"({"scene": "s.json", "list": [
      {"cloth.material.density": 0.1, "obstacles.0.sphere.density": 2},
      {"dt": 0.1}, {"dt": 0.1}, {"dt": 0.1}, {}]})");
  EXPECT_EQ(names(b), (std::vector<std::string>{"cloth.material.density-0.1_obstacles.0.sphere.density-2",
                                                "dt-0.1", "dt-0.1-2", "dt-0.1-3", "s"}));
}

TEST_F(BatchSpecTest, StringsThatLookLikeJsonStayStrings) {
  const BatchSpec b = read(R"({"scene": "s.json", "set": {"render.caption": "12", "name": "a b/c"},
                               "list": [{"render.caption": "plain"}]})");
  ASSERT_EQ(b.jobs[0].overrides.size(), 3u);
  EXPECT_EQ(b.jobs[0].overrides[0].assignment(), "render.caption=\"12\"");
  EXPECT_EQ(b.jobs[0].overrides[1].assignment(), "name=a b/c");
  EXPECT_EQ(b.jobs[0].name, "caption-plain");
  EXPECT_EQ(tissu::job_name_of({{"name", "a b/c"}}), "name-a-b-c");
}

TEST_F(BatchSpecTest, TheHashFollowsTheContentNotTheLayout) {
  const std::string a = read(R"({"scene": "s.json", "grid": {"dt": [1, 2]}})").hash;
  const std::string b = read("// same\n{\"grid\": {\"dt\": [1, 2]},\n \"scene\": \"s.json\"}").hash;
  const std::string c = read(R"({"scene": "s.json", "grid": {"dt": [1, 3]}})").hash;
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(a.size(), 16u);
}

TEST(BatchHelpers, IndexRangesShellQuotesCsvFields) {
  EXPECT_EQ(tissu::index_ranges({0, 1, 2, 3, 5, 7, 8}), "0-3,5,7-8");
  EXPECT_EQ(tissu::index_ranges({4}), "4");
  EXPECT_EQ(tissu::shell_quote("/a b/it's"), "'/a b/it'\\''s'");
  EXPECT_EQ(tissu::shell_word("scenes/a-1.json"), "scenes/a-1.json");
  EXPECT_EQ(tissu::shell_word("my scene.json"), "'my scene.json'");
  EXPECT_EQ(tissu::csv_field("plain"), "plain");
  EXPECT_EQ(tissu::csv_field("a, \"b\""), "\"a, \"\"b\"\"\"");
}

}  // namespace
