// rtabmap-dataset --localization: a run localised against a map made by --slam leaves the
// database as it was and writes every frame's pose in the map (DIR/localization.tum).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "SimSlam.h"
#include "common/ToolRun.h"

namespace rtabmap {
namespace {

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

int tumLines(const std::string& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string l; std::getline(in, l);) lines += (!l.empty() && l[0] != '#') ? 1 : 0;
  return lines;
}

TEST(DatasetToolLocalization, TheLapDrivenAgainLocalisesWithoutWriting) {
  std::string why;
  const std::string data = test::simDataset("loop", &why);
  ASSERT_FALSE(data.empty()) << why;
  test::TempDir dir("rtabmap_dataset_localization");
  const std::string out = dir.file("out");
  const std::string config = std::string(RTABMAP_CORE_SOURCE_DIR) + "/../config/sim_robot.ini";
  // The laser alone, so localization rests on proximity detection (the global scan map).
  const std::string robot = "--format sim --odom wheel --config " + config + " --Kp/MaxFeatures -1 --Reg/Strategy 1 ";
  const test::ToolRun slam =
      test::runTool("dataset", robot + "--slam --max-frames 200 --output " + out + " --json " + data, dir);
  ASSERT_EQ(slam.exitCode, 0) << slam.stderrText;
  EXPECT_GT(test::lastJsonLine(slam.stdoutText)["nodes"].get<int>(), 50);
  const std::string db = out + "/rtabmap.db";
  const std::string before = fileBytes(db);

  // The start of the lap again, from where the map starts (past the map's end the robot sees
  // mostly unmapped corridor: the global scan map's ratio test rightly refuses those matches).
  const test::ToolRun loc = test::runTool("dataset",
                                          robot + "--localization --max-frames 40 --RGBD/StartAtOrigin true "
                                                  "--RGBD/ProximityGlobalScanMap true --output " +
                                              out + " --json " + data,
                                          dir);
  ASSERT_EQ(loc.exitCode, 0) << loc.stderrText;
  const nlohmann::json j = test::lastJsonLine(loc.stdoutText);
  EXPECT_EQ(j["frames"], 40);
  EXPECT_EQ(j["nodes"], 0) << "localization adds no node";
  EXPECT_GT(j["localizations"].get<int>(), 0);
  EXPECT_EQ(tumLines(out + "/localization.tum"), 40) << "one pose in the map per frame";
  EXPECT_EQ(fileBytes(db), before) << "localization must not modify the database";
}

}  // namespace
}  // namespace rtabmap
