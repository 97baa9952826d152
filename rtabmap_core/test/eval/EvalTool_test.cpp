// rtabmap-eval run as a subprocess: each command's --json line (the last line of stdout).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/eval/Trajectory.h"

using rtabmap::Trajectory;
using rtabmap::TrajectoryFormat;
using rtabmap::Transform;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;

namespace {

struct ToolRun {
  int exitCode = -1;
  std::string out;
  nlohmann::json last;  // the parsed last line, if it is JSON
};

ToolRun run(const std::string& args) {
  ToolRun r;
  const std::string command = rtabmap::test::toolPath("eval") + " " + args + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::string line, lastLine;
  std::istringstream lines(r.out);
  while (std::getline(lines, line)) {
    if (!line.empty()) lastLine = line;
  }
  r.last = nlohmann::json::parse(lastLine, nullptr, false);
  return r;
}

Trajectory circle(size_t n) {
  Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.05 * static_cast<double>(i);
    t.add(50.0 + 0.1 * static_cast<double>(i), Transform(5 * std::cos(a), 5 * std::sin(a), 0.01 * i, 0, 0, a + M_PI / 2));
  }
  return t;
}

}  // namespace

TEST(EvalTool, AteRpeKittiOnATrajectoryAndItsRigidCopy) {
  TempDir dir;
  const Trajectory gt = circle(300);
  Trajectory est;
  const Transform T(1, 2, 3, 0.1, 0.2, 0.3);
  for (const auto& p : gt.poses) est.add(p.stamp + 0.005, T * p.pose);
  rtabmap::writeTrajectory(dir.file("gt.txt"), gt, TrajectoryFormat::kTum);
  rtabmap::writeTrajectory(dir.file("est.txt"), est, TrajectoryFormat::kTum);

  ToolRun r = run("ate --gt " + dir.file("gt.txt") + " --est " + dir.file("est.txt") + " --json --save-aligned " +
              dir.file("aligned.txt"));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  ASSERT_TRUE(r.last.is_object()) << r.out;
  EXPECT_EQ(r.last["command"], "ate");
  EXPECT_EQ(r.last["associated"], 300);
  EXPECT_LT(r.last["rmse"].get<double>(), 1e-6);
  EXPECT_LT(r.last["translation"]["max"].get<double>(), 1e-6);
  EXPECT_NE(r.out.find("ATE: 300 poses associated"), std::string::npos) << r.out;
  const Trajectory aligned = rtabmap::readTrajectory(dir.file("aligned.txt"));
  EXPECT_LT((aligned[10].pose.translation() - gt[10].pose.translation()).norm(), 1e-6);

  r = run("ate --gt " + dir.file("gt.txt") + " --est " + dir.file("est.txt") + " --no-align --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_GT(r.last["rmse"].get<double>(), 1.0);

  r = run("rpe --gt " + dir.file("gt.txt") + " --est " + dir.file("est.txt") + " --unit m --delta 2 --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["unit"], "m");
  EXPECT_GT(r.last["pairs"].get<int>(), 200);
  EXPECT_LT(r.last["translation"]["max"].get<double>(), 1e-6);
  EXPECT_LT(r.last["rotation_deg"]["max"].get<double>(), 1e-4);

  // KITTI files (index stamps): a 150 m path is long enough for the 100 m segments.
  Trajectory line;
  Trajectory longer;
  for (int i = 0; i < 151; ++i) {
    line.add(i, Transform(i, 0, 0));
    longer.add(i, Transform(1.02 * i, 0, 0));
  }
  rtabmap::writeTrajectory(dir.file("gt_kitti.txt"), line, TrajectoryFormat::kKitti);
  rtabmap::writeTrajectory(dir.file("est_kitti.txt"), longer, TrajectoryFormat::kKitti);
  r = run("kitti --gt " + dir.file("gt_kitti.txt") + " --est " + dir.file("est_kitti.txt") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["frames"], 151);
  EXPECT_EQ(r.last["segments"], 5);  // starts 0..40 for 100 m (last frame f + 101 <= 150)
  EXPECT_NEAR(r.last["translation_percent"].get<double>(), 2.0 * 101.0 / 100.0, 1e-6);
}

TEST(EvalTool, RelationsAndPr) {
  TempDir dir;
  writeText(dir.file("est.txt"), "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0.7071067811865476 0.7071067811865476\n");
  writeText(dir.file("r.relations"), "1.0 2.0 1 0.1 0 0 0 1.5707963267948966\n1.0 9.0 1 0 0 0 0 0\n");
  ToolRun r = run("relations --relations " + dir.file("r.relations") + " --est " + dir.file("est.txt") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["command"], "relations");
  EXPECT_EQ(r.last["used"], 1);
  EXPECT_EQ(r.last["skipped"], 1);
  EXPECT_NEAR(r.last["translation"]["mean"].get<double>(), 0.1, 1e-9);

  writeText(dir.file("d.txt"), "1 0 0\n2 0 0\n3 1 0.9\n4 2 0.4\n");
  writeText(dir.file("gt.txt"), "0 0 0 0\n0 0 0 0\n1 0 0 0\n0 0 0 0\n");
  r = run("pr --gt " + dir.file("gt.txt") + " --detections " + dir.file("d.txt") + " --json --curve " +
          dir.file("curve.txt"));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["gt_type"], "matrix");
  EXPECT_EQ(r.last["positives"], 1);
  EXPECT_EQ(r.last["true_positives"], 1);
  EXPECT_EQ(r.last["false_positives"], 1);
  EXPECT_DOUBLE_EQ(r.last["precision"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(r.last["recall_at_100_precision"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(r.last["threshold_at_100_precision"].get<double>(), 0.9);
  EXPECT_NE(rtabmap::test::readText(dir.file("curve.txt")).find("0.9 1 1 1 0"), std::string::npos);

  // Poses ground truth with the ambiguous band: image 4 (x = 1.5) matched to image 1 (x = 0) is
  // false with two bands, neither with a band to 2 m.
  writeText(dir.file("poses.txt"), "1 0 0 0 0 0 0 1\n2 5 0 0 0 0 0 1\n3 0.2 0 0 0 0 0 1\n4 1.5 0 0 0 0 0 1\n");
  writeText(dir.file("d2.txt"), "3 1 0.9\n4 1 0.8\n");
  const std::string poses = "pr --gt " + dir.file("poses.txt") + " --detections " + dir.file("d2.txt") +
                            " --gt-type poses --format tum --distance 0.5 --angle 0 --min-gap 1 --json";
  r = run(poses);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["false_positives"], 1);
  EXPECT_EQ(r.last["ambiguous"], 0);
  r = run(poses + " --ambiguous-distance 2");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["true_positives"], 1);
  EXPECT_EQ(r.last["false_positives"], 0);
  EXPECT_EQ(r.last["ambiguous"], 1);
  EXPECT_DOUBLE_EQ(r.last["precision"].get<double>(), 1.0);
  EXPECT_NE(r.out.find("1 in the ambiguous band"), std::string::npos) << r.out;
  EXPECT_EQ(run(poses + " --ambiguous-distance 0.3").exitCode, 2);  // narrower than the loop

  // --viewing-direction: image 3 rolled 90 degrees about its x axis (the viewing direction) is a
  // loop with image 1 only when the roll does not count.
  writeText(dir.file("rolled.txt"),
            "1 0 0 0 0 0 0 1\n2 5 0 0 0 0 0 1\n3 0.2 0 0 0.7071067811865476 0 0 0.7071067811865476\n");
  writeText(dir.file("d3.txt"), "3 1 0.9\n");
  const std::string rolled = "pr --gt " + dir.file("rolled.txt") + " --detections " + dir.file("d3.txt") +
                             " --gt-type poses --format tum --distance 0.5 --angle 30 --min-gap 1 --json";
  r = run(rolled);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["false_positives"], 1);
  r = run(rolled + " --viewing-direction");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["true_positives"], 1);
  EXPECT_EQ(r.last["false_positives"], 0);
}

TEST(EvalTool, AcesOdometryThroughTheTool) {
  const std::string log = rtabmap::test::shippedDataPath("radish/aces.clf.bz2");
  const std::string rel = rtabmap::test::shippedDataPath("radish/aces.relations");
  if (log.empty() || rel.empty()) GTEST_SKIP() << "data/radish/aces.* absent";
  TempDir dir;
  ToolRun r = run("trajectory --dataset carmen --input " + log + " --output " + dir.file("odom.txt") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["poses"], 7374);
  r = run("relations --relations " + rel + " --est " + dir.file("odom.txt") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["used"], 1279);
  EXPECT_NEAR(r.last["translation"]["mean"].get<double>(), 0.549, 0.549 * 0.01);
}

TEST(EvalTool, PathAgainstAG2oReferenceWithoutStamps) {
  // Reference: a g2o graph's vertices along an L (ids, no stamps); estimate: the L every 0.1 m,
  // moved rigidly, with one position 0.8 m off the path.
  TempDir dir;
  writeText(dir.file("ref.g2o"), "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 5 0 0\nVERTEX_SE2 2 5 5 1.5707963\n"
                                  "EDGE_SE2 0 1 5 0 0 1 0 0 1 0 1\n");
  const Transform moved(1.0, 2.0, 0.0, 0.0, 0.0, 0.5);
  Trajectory est;
  for (int i = 0; i <= 100; ++i) {
    const double s = 0.1 * i;
    Transform p = s <= 5.0 ? Transform(s, 0, 0, 0, 0, 0) : Transform(5.0, s - 5.0, 0, 0, 0, M_PI / 2);
    if (i == 70) p = Transform(5.8, 2.0, 0, 0, 0, M_PI / 2);  // beyond --trim 0.5: out of the fit
    est.add(10.0 + i, moved * p);
  }
  rtabmap::writeTrajectory(dir.file("est.txt"), est, TrajectoryFormat::kTum);
  ToolRun r = run("path --ref " + dir.file("ref.g2o") + " --est " + dir.file("est.txt") + " --worst 1 --aligned " +
                  dir.file("aligned.txt") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.last["command"], "path");
  EXPECT_EQ(r.last["reference_poses"], 3);
  EXPECT_NEAR(r.last["reference_length"].get<double>(), 10.0, 1e-9);
  EXPECT_EQ(r.last["estimated_poses"], 101);
  EXPECT_NEAR(r.last["deviation"]["max"].get<double>(), 0.8, 1e-6);
  EXPECT_LT(r.last["deviation"]["median"].get<double>(), 1e-6);
  EXPECT_NE(r.out.find("  80.000: 0.8000"), std::string::npos) << r.out;  // stamp 10 + 70
  const Trajectory aligned = rtabmap::readTrajectory(dir.file("aligned.txt"));
  ASSERT_EQ(aligned.size(), est.size());
  EXPECT_NEAR(aligned[100].pose.x(), 5.0, 1e-6);
  EXPECT_NEAR(aligned[100].pose.y(), 5.0, 1e-6);
  EXPECT_EQ(run("path --ref " + dir.file("ref.g2o")).exitCode, 2);  // --est missing
  EXPECT_EQ(run("path --ref " + dir.file("ref.g2o") + " --est " + dir.file("est.txt") + " --init nearest").exitCode, 2);
  EXPECT_EQ(run("path --ref " + dir.file("ref.g2o") + " --est " + dir.file("est.txt") + " --trim 0").exitCode, 2);
}

TEST(EvalTool, UsageErrorsExitWithTwo) {
  EXPECT_EQ(run("").exitCode, 2);
  EXPECT_EQ(run("nosuchcommand").exitCode, 2);
  EXPECT_EQ(run("ate --gt x.txt").exitCode, 2);  // --est missing
  EXPECT_EQ(run("rpe --gt a --est b --unit parsecs").exitCode, 2);
  ToolRun help = run("--help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("relations"), std::string::npos);
  help = run("pr --help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("query_id matched_id confidence"), std::string::npos) << help.out;
  // Bad data is a failure of the run (1), naming the file and line.
  TempDir dir;
  writeText(dir.file("bad.txt"), "1 0 0 0 0 0 0 1\n2 0 0\n");
  EXPECT_EQ(run("ate --gt " + dir.file("bad.txt") + " --est " + dir.file("bad.txt") + " --format tum").exitCode, 1);
}
