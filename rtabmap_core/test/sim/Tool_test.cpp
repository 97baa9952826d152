// rtabmap-sim as a user runs it: options, the JSON summary, the folder, determinism, --bag.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "common/TestData.h"
#include "rtabmap_core/sim/SimDatasetReader.h"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string out;  // stdout and stderr together when merged
};

Result run(const std::string& args, bool mergeStderr = true, const std::string& env = "") {
  const std::string command = env + (env.empty() ? "" : " ") + rtabmap::test::toolPath("sim") + " " + args + (mergeStderr ? " 2>&1" : " 2>/dev/null");
  Result r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string lastLine(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const size_t nl = t.rfind('\n');
  return nl == std::string::npos ? t : t.substr(nl + 1);
}

const std::string kSmall = "--width 96 --height 72 --rate 1 --duration 6 --texture-size 64 --threads 1";

}  // namespace

TEST(SimTool, WritesTheFolderAndSummarisesItInJson) {
  rtabmap::test::TempDir dir("rtabmap_sim_tool");
  const std::string out = dir.path() + "/loop";
  const Result r = run("--scenario loop --seed 3 --output " + out + " " + kSmall + " --lidar3d --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(lastLine(r.out));
  EXPECT_EQ(j["scenario"], "loop");
  EXPECT_EQ(j["seed"], 3);
  EXPECT_EQ(j["frames"], 7);
  EXPECT_DOUBLE_EQ(j["duration_s"].get<double>(), 6.0);
  EXPECT_GT(j["distance_m"].get<double>(), 1.0);
  EXPECT_GT(j["fps"].get<double>(), 0.0);
  EXPECT_EQ(j["output"], out);
  ASSERT_EQ(j["sessions"].size(), 1u);
  EXPECT_EQ(j["sessions"][0]["groundtruth"], out + "/groundtruth.txt");
  for (const char* f : {"info.yaml", "calib/rgb.yaml", "calib/right.yaml", "transforms.txt", "frames.txt", "groundtruth.txt",
                        "odometry.txt", "imu.txt", "rgb/000006.png", "depth/000006.png", "right/000006.png",
                        "scan_urg/000006.bin", "scan_utm/000006.bin", "lidar/000006.bin"}) {
    EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  }
  rtabmap::sim::SimDatasetReader reader(out);
  EXPECT_EQ(reader.totalFrames(), 7);
  EXPECT_EQ(reader.meta().options.at("width"), "96");
  // Not over a previous output unless asked; with --overwrite, the same bytes again.
  EXPECT_EQ(run("--scenario loop --seed 3 --output " + out + " " + kSmall).code, 1);
  std::ifstream before(out + "/info.yaml");
  const std::string info((std::istreambuf_iterator<char>(before)), std::istreambuf_iterator<char>());
  ASSERT_EQ(run("--scenario loop --seed 3 --output " + out + " " + kSmall + " --lidar3d --overwrite --threads 2").code, 0);
  std::ifstream after(out + "/info.yaml");
  EXPECT_EQ(info, std::string((std::istreambuf_iterator<char>(after)), std::istreambuf_iterator<char>()));
}

TEST(SimTool, MultisessionWritesOneReadableFolderPerRun) {
  rtabmap::test::TempDir dir("rtabmap_sim_tool");
  const std::string out = dir.path() + "/multi";
  const Result r = run("--scenario multisession --seed 2 --output " + out + " " + kSmall + " --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(lastLine(r.out));
  ASSERT_EQ(j["sessions"].size(), 3u);
  EXPECT_EQ(j["frames"], 21);
  double previousEnd = 0.0;
  for (int k = 1; k <= 3; ++k) {
    rtabmap::sim::SimDatasetReader reader(out + "/session" + std::to_string(k));
    EXPECT_EQ(reader.meta().session, "session" + std::to_string(k));
    const auto first = reader.readFrame(0, false, false);
    EXPECT_TRUE(first.odometry.isIdentity(1e-9));
    EXPECT_GT(first.stamp, previousEnd);  // sessions follow each other in time
    previousEnd = reader.readFrame(reader.totalFrames() - 1, false, false).stamp;
  }
  EXPECT_TRUE(fs::exists(out + "/info.yaml"));
}

TEST(SimTool, BagNeedsTheConverterAndSaysSo) {
  if (fs::exists(rtabmap::test::toolPath("bag"))) GTEST_SKIP() << "rtabmap-bag is built: this checks its absence";
  rtabmap::test::TempDir dir("rtabmap_sim_tool");
  const std::string out = dir.path() + "/corridor";
  const Result r = run("--scenario corridor --output " + out + " " + kSmall + " --bag " + dir.path() + "/x.bag", true,
                       "/usr/bin/env PATH=/nonexistent");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("rtabmap-bag"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out + "/info.yaml"));  // the folder was written all the same
  EXPECT_FALSE(fs::exists(dir.path() + "/x.bag"));
}

// --bag hands each session folder to rtabmap-bag (`--format sim DIR BAG`), one bag per session,
// with the converter's stdout kept off ours so --json stays the last line. A stand-in converter
// on PATH records its calls; where the real rtabmap-bag is built next to rtabmap-sim it is used
// instead (it comes first), and the bags must then exist all the same.
TEST(SimTool, BagGoesThroughTheConverterOneBagPerSession) {
  rtabmap::test::TempDir dir("rtabmap_sim_tool");
  const bool realConverter = fs::exists(rtabmap::test::toolPath("bag"));
  const std::string fakeDir = dir.path() + "/fake";
  fs::create_directories(fakeDir);
  {
    std::ofstream script(fakeDir + "/rtabmap-bag");
    script << "#!/bin/sh\necho \"$@\" >> \"$(dirname \"$0\")/calls.txt\"\necho converter chatter\n: > \"$4\"\n";
  }
  fs::permissions(fakeDir + "/rtabmap-bag", fs::perms::owner_all);
  const std::string out = dir.path() + "/multi";
  const std::string bag = dir.path() + "/run.bag";
  const Result r = run("--scenario multisession --seed 2 --output " + out + " " + kSmall + " --bag " + bag + " --json", false,
                       "/usr/bin/env PATH=" + fakeDir + ":/usr/bin:/bin");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(lastLine(r.out));
  ASSERT_EQ(j["bags"].size(), 3u);
  for (int k = 1; k <= 3; ++k) {
    const std::string expected = dir.path() + "/run_session" + std::to_string(k) + ".bag";
    EXPECT_EQ(j["bags"][k - 1], expected);
    EXPECT_TRUE(fs::exists(expected)) << expected;
  }
  if (realConverter) return;
  EXPECT_EQ(r.out.find("converter chatter"), std::string::npos) << "the converter's stdout reached ours:\n" << r.out;
  std::ifstream calls(fakeDir + "/calls.txt");
  std::string line;
  for (int k = 1; k <= 3; ++k) {
    ASSERT_TRUE(std::getline(calls, line)) << "call " << k;
    const std::string session = "session" + std::to_string(k);
    EXPECT_EQ(line, "--format sim " + out + "/" + session + " " + dir.path() + "/run_" + session + ".bag");
  }
  EXPECT_FALSE(std::getline(calls, line)) << "an extra call: " << line;

  // A converter that fails makes rtabmap-sim fail, naming the command; the folder stays.
  {
    std::ofstream script(fakeDir + "/rtabmap-bag");
    script << "#!/bin/sh\nexit 3\n";
  }
  const std::string single = dir.path() + "/corridor";
  const Result failed = run("--scenario corridor --output " + single + " " + kSmall + " --bag " + bag, true,
                            "/usr/bin/env PATH=" + fakeDir + ":/usr/bin:/bin");
  EXPECT_EQ(failed.code, 1) << failed.out;
  EXPECT_NE(failed.out.find("--format sim " + single), std::string::npos) << failed.out;
  EXPECT_NE(failed.out.find("exit code 3"), std::string::npos) << failed.out;
  EXPECT_TRUE(fs::exists(single + "/info.yaml"));
}

TEST(SimTool, UsageErrorsAndHelp) {
  EXPECT_EQ(run("--scenario nowhere --output /tmp/x").code, 2);
  EXPECT_EQ(run("--scenario loop").code, 2);  // no --output
  EXPECT_EQ(run("--scenario loop --output /tmp/x --width 0").code, 2);
  const Result help = run("--help");
  EXPECT_EQ(help.code, 0);
  for (const char* s : {"groundtruth.txt", "scan_urg", "calib/rgb.yaml", "multisession", "--bag", "--seed"}) {
    EXPECT_NE(help.out.find(s), std::string::npos) << s;
  }
}
