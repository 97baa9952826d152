// The rtabmap-bag command line: exit codes (0 done, 1 the run failed, 2 the command line was
// wrong), messages that name the problem, no bag left behind by a failed run, and --json.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/TestData.h"

namespace {

struct ToolRun {
  int exitCode = -1;
  std::string output;  // stdout and stderr
  std::string lastLine;
};

ToolRun runBag(const std::string& args) {
  const std::string command = std::string(RTABMAP_ROS_TOOLS_DIR) + "/rtabmap-bag " + args + " 2>&1";
  ToolRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  while (fgets(buffer, sizeof(buffer), pipe)) {
    run.output += buffer;
    run.lastLine = buffer;
  }
  const int status = pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

// A tiny CARMEN log: two FLASER scans of 180 beams with odometry, one ODOM in between.
std::string writeTinyLog(const std::string& path, bool corruptSecondScan = false) {
  std::ofstream out(path);
  for (int k = 0; k < 2; ++k) {
    out << "FLASER 180";
    for (int i = 0; i < 180; ++i) {
      out << " " << (corruptSecondScan && k == 1 && i == 5 ? std::string("abc") : std::to_string(1.0 + 0.01 * i));
    }
    out << " 0.0 0.0 0.0 " << 0.1 * k << " 0.0 0.0 " << 100.0 + k << " host " << 100.0 + k << "\n";
    if (k == 0) out << "ODOM 0.05 0.0 0.0 0.1 0.0 0.0 100.5 host 100.5\n";
  }
  return path;
}

}  // namespace

TEST(RtabmapBagTool, ConvertsAndPrintsAJsonSummaryLast) {
  rtabmap::test::TempDir dir("rtabmap_bag_cli");
  const std::string log = writeTinyLog(dir.file("tiny.clf"));
  const ToolRun run = runBag("--json --format carmen " + log + " " + dir.file("tiny.bag"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(run.lastLine);
  EXPECT_EQ(j["frames"], 2);
  EXPECT_EQ(j["topics"]["/scan"], 2);
  EXPECT_EQ(j["topics"]["/odom"], 3);
  EXPECT_EQ(j["topics"]["/tf_static"], 1);
  EXPECT_DOUBLE_EQ(j["end"].get<double>(), 101.0);
  EXPECT_GT(j["bytes"].get<double>(), 0.0);
  EXPECT_TRUE(std::filesystem::exists(dir.file("tiny.bag")));

  const ToolRun human = runBag("--format carmen " + log + " " + dir.file("tiny2.bag"));
  ASSERT_EQ(human.exitCode, 0) << human.output;
  EXPECT_NE(human.output.find("/scan"), std::string::npos) << human.output;
  EXPECT_NE(human.output.find("messages/s"), std::string::npos) << human.output;
}

TEST(RtabmapBagTool, CommandLineMistakesExitWith2) {
  ToolRun run = runBag("/a.clf /b.bag");
  EXPECT_EQ(run.exitCode, 2);
  EXPECT_NE(run.output.find("--format is required"), std::string::npos) << run.output;
  run = runBag("--format carmn /a.clf /b.bag");
  EXPECT_EQ(run.exitCode, 2);
  EXPECT_NE(run.output.find("unknown --format 'carmn'"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("carmen"), std::string::npos) << run.output;
  run = runBag("--format carmen /a.clf");
  EXPECT_EQ(run.exitCode, 2);
  EXPECT_NE(run.output.find("INPUT and OUTPUT"), std::string::npos) << run.output;
  run = runBag("--format carmen --compression zip /a.clf /b.bag");
  EXPECT_EQ(run.exitCode, 2);
  EXPECT_NE(run.output.find("zip"), std::string::npos) << run.output;
  run = runBag("--bench");
  if (!std::getenv("RTABMAP_DATA_DIR")) {
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.output.find("--data"), std::string::npos) << run.output;
  }
}

TEST(RtabmapBagTool, FailedRunsExitWith1AndLeaveNoBag) {
  rtabmap::test::TempDir dir("rtabmap_bag_cli_fail");
  ToolRun run = runBag("--format carmen " + dir.file("absent.clf") + " " + dir.file("out.bag"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("absent.clf"), std::string::npos) << run.output;

  const std::string log = writeTinyLog(dir.file("tiny.clf"));
  run = runBag("--format carmen " + log + " " + dir.file("no/such/dir/out.bag"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("cannot write the bag"), std::string::npos) << run.output;

  const std::string bad = writeTinyLog(dir.file("bad.clf"), true);
  run = runBag("--format carmen " + bad + " " + dir.file("bad.bag"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("bad.clf"), std::string::npos) << run.output;  // the reader names the file
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.bag")));
}
