// rtabmap-dataset end to end on a rendered sequence written in the 7-Scenes layout, and on the
// real 7-Scenes frames when ../shared/data has them.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/TestData.h"
#include "odometry/VisualOdometryTestUtil.h"

namespace rtabmap {
namespace {

struct ToolRun {
  int exitCode = -1;
  std::string out;
};

ToolRun runTool(const std::string& arguments) {
  ToolRun r;
  const std::string command = test::toolPath("dataset") + " " + arguments + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) r.out += buffer.data();
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

nlohmann::json lastLine(const std::string& out) {
  std::istringstream in(out);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return nlohmann::json::parse(last);
}

// Frames of the synthetic trajectory as frame-N.color.png / depth.png / pose.txt.
void writeSevenScenes(const std::string& dir, int n) {
  const CameraModel model = test::SyntheticRoom::camera();
  std::ofstream intrinsics(dir + "/camera-intrinsics.txt");
  intrinsics << model.fx() << " 0 " << model.cx() << "\n0 " << model.fy() << " " << model.cy() << "\n0 0 1\n";
  for (int i = 0; i < n; ++i) {
    const SensorData d = test::rgbdFrame(i);
    char name[64];
    std::snprintf(name, sizeof(name), "%s/frame-%06d", dir.c_str(), i);
    cv::Mat mm;
    d.depthOrRightRaw().convertTo(mm, CV_16UC1, 1000.0);
    cv::imwrite(std::string(name) + ".color.png", d.imageRaw());
    cv::imwrite(std::string(name) + ".depth.png", mm);
    const Eigen::Matrix4d pose = (test::trajectoryPose(i) * model.localTransform()).toMatrix4d();
    std::ofstream p(std::string(name) + ".pose.txt");
    p.precision(12);
    for (int r = 0; r < 4; ++r) p << pose(r, 0) << " " << pose(r, 1) << " " << pose(r, 2) << " " << pose(r, 3) << "\n";
  }
}

TEST(DatasetTool, OdometryOverASequenceWritesTumAndJson) {
  test::TempDir dir("rtabmap_dataset_tool");
  const std::string data = dir.file("scenes");
  std::filesystem::create_directories(data);
  writeSevenScenes(data, 30);
  for (const char* approach : {"f2m", "f2f"}) {
    SCOPED_TRACE(approach);
    const std::string out = dir.file(std::string("out_") + approach);
    const std::string jsonFile = dir.file(std::string(approach) + ".json");
    const ToolRun run = runTool(std::string("--format 7scenes --odom ") + approach + " --output " + out + " --json " +
                                jsonFile + " " + data);
    ASSERT_EQ(run.exitCode, 0) << run.out;
    const nlohmann::json j = lastLine(run.out);
    EXPECT_EQ(j["frames"], 30);
    EXPECT_EQ(j["lost"], 0);
    EXPECT_GT(j["odom_ms_median"].get<double>(), 0.0);
    EXPECT_GE(j["odom_ms_max"].get<double>(), j["odom_ms_median"].get<double>());
    EXPECT_LT(j["odom_ate_rmse"].get<double>(), 0.02);
    // odom.tum: one pose per frame; the JSON file holds the same summary.
    std::ifstream tum(out + "/odom.tum");
    int lines = 0;
    for (std::string l; std::getline(tum, l);) lines += (!l.empty() && l[0] != '#') ? 1 : 0;
    EXPECT_EQ(lines, 30);
    std::ifstream saved(jsonFile);
    std::string savedLine;
    std::getline(saved, savedLine);
    EXPECT_EQ(nlohmann::json::parse(savedLine)["frames"], 30);
  }
  // Parameters pass through (--Group/Name value), and the human summary without --json.
  const ToolRun text = runTool("--format 7scenes --odom f2m --max-frames 10 --Vis/MaxFeatures 300 " + data);
  EXPECT_EQ(text.exitCode, 0);
  EXPECT_NE(text.out.find("ATE"), std::string::npos) << text.out;
}

// Stamps since 1970 (the simulator's, TUM's, EuRoC's) keep their fraction in --frames-csv:
// written with 9 significant digits, 10 Hz frames all read 1.7e+09.
TEST(DatasetTool, FramesCsvKeepsEachFrameStamp) {
  test::TempDir dir("rtabmap_dataset_stamps");
  const std::string data = dir.file("sim");
  const std::string sim = test::toolPath("sim") + " --scenario corridor --duration 2 --rate 10 --width 64 --height 48" +
                          " --no-stereo --no-urg --output " + data + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(sim.c_str()), 0);
  const std::string csv = dir.file("frames.csv");
  const ToolRun run = runTool("--format sim --odom wheel --json --frames-csv " + csv + " " + data);
  ASSERT_EQ(run.exitCode, 0) << run.out;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> stamps;
  while (std::getline(in, line)) stamps.push_back(std::stod(line.substr(line.find(',') + 1)));
  ASSERT_EQ(static_cast<int>(stamps.size()), lastLine(run.out)["frames"].get<int>());
  ASSERT_GE(stamps.size(), 10u);
  EXPECT_GT(stamps.front(), 1.0e9);
  for (size_t i = 1; i < stamps.size(); ++i) EXPECT_NEAR(stamps[i] - stamps[i - 1], 0.1, 1e-4) << "frame " << i;
}

TEST(DatasetTool, UsageErrors) {
  EXPECT_EQ(runTool("/nonexistent").exitCode, 2);                           // no --format
  EXPECT_EQ(runTool("--format 7scenes --odom icp /nonexistent").exitCode, 1);  // unknown approach
  EXPECT_EQ(runTool("--format 7scenes --Vis/NoSuchKey 1 /nonexistent").exitCode, 2);
  EXPECT_EQ(runTool("--format 7scenes /nonexistent").exitCode, 1);         // not a dataset
}

TEST(DatasetTool, SevenScenesShortRun) {
  RTABMAP_REQUIRE_DATA(path, "rgbd_7scenes");
  const ToolRun run = runTool("--format 7scenes --odom f2m --max-frames 60 --json " + path);
  ASSERT_EQ(run.exitCode, 0) << run.out;
  const nlohmann::json j = lastLine(run.out);
  EXPECT_EQ(j["frames"], 60);
  EXPECT_EQ(j["lost"], 0);
  // KinectFusion's poses as reference; 60 frames of hand-held motion.
  EXPECT_LT(j["odom_ate_rmse"].get<double>(), 0.03);
}

}  // namespace
}  // namespace rtabmap
