// rtabmap-console: appearance-only loop closure over an image folder, its files, --json line,
// scoring with --gt and command-line errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/TestData.h"
#include "common/ToolRun.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap {
namespace {

namespace fs = std::filesystem;

TEST(ConsoleTool, LoopClosuresOnRealImagesWithGroundTruth) {
  RTABMAP_REQUIRE_DATA(scenes, "rgbd_7scenes");
  test::TempDir dir;
  const int n = 150;
  fs::create_directories(dir.file("images"));
  std::vector<Transform> poses;
  auto reader = openDatasetReader("7scenes", scenes);
  DatasetRecord r;
  while (static_cast<int>(poses.size()) < n && reader->next(r)) poses.push_back(r.data.groundTruth());
  for (int i = 0; i < n; ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "frame-%06d.color.jpg", i);
    fs::create_symlink(fs::path(scenes) / name, dir.file("images/" + std::to_string(i + 1) + ".jpg"));
  }
  // Ground-truth matrix: within 0.3 m and 30 degrees.
  std::ofstream gt(dir.file("gt.txt"));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Transform d = poses[i].inverse() * poses[j];
      const double angle = Eigen::AngleAxisd(d.toEigen().linear()).angle();
      gt << (i != j && d.toEigen().translation().norm() <= 0.3 && angle <= M_PI / 6 ? 1 : 0) << (j + 1 < n ? " " : "\n");
    }
  }
  gt.close();
  const auto run = test::runTool("console", "--json --gt " + dir.file("gt.txt") + " --output " + dir.file("out") + " " +
                                                dir.file("images"),
                                 dir);
  ASSERT_EQ(run.exitCode, 0) << run.stderrText;
  const auto j = test::lastJsonLine(run.stdoutText);
  EXPECT_EQ(j["images"], n);
  EXPECT_GT(j["loop_closures"].get<int>(), 50);
  EXPECT_GT(j["mean_update_ms"].get<double>(), 0.0);
  EXPECT_GE(j["max_update_ms"].get<double>(), j["mean_update_ms"].get<double>());
  EXPECT_GT(j["max_wm_size"].get<int>(), 100);
  EXPECT_GT(j["max_vocabulary_size"].get<int>(), 1000);
  EXPECT_EQ(j["false_positives"], 0);
  EXPECT_GT(j["recall_at_100_precision"].get<double>(), 0.5);
  // The database holds every location; the log one line per image.
  db::Database saved(dir.file("out/rtabmap.db"), db::DatabaseOptions());
  EXPECT_GE(saved.nodeIds().size(), static_cast<size_t>(n) - j["rehearsal_merges"].get<int>());
  std::ifstream log(dir.file("out/log.txt"));
  int lines = 0;
  for (std::string line; std::getline(log, line);) lines += !line.empty() && line[0] != '#';
  EXPECT_EQ(lines, n);
}

TEST(ConsoleTool, ErrorsAreClear) {
  test::TempDir dir;
  auto missing = test::runTool("console", "", dir);
  EXPECT_EQ(missing.exitCode, 2);
  auto absent = test::runTool("console", "--output " + dir.file("out") + " " + dir.file("nowhere"), dir);
  EXPECT_EQ(absent.exitCode, 1);
  EXPECT_NE(absent.stderrText.find("nowhere"), std::string::npos) << absent.stderrText;
  auto badParam = test::runTool("console", "--Kp/NndrRato 0.7 " + dir.path(), dir);
  EXPECT_EQ(badParam.exitCode, 2);
  EXPECT_NE(badParam.stderrText.find("Kp/NndrRatio"), std::string::npos) << badParam.stderrText;
}

}  // namespace
}  // namespace rtabmap
