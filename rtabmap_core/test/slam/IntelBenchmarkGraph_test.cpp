// 2D lidar SLAM on real data against an independent map: the first 2,500 scans of the Radish
// Intel lab log mapped by rtabmap-dataset with config/lidar2d.ini (wheel odometry, ICP
// neighbour links, proximity loop closures), and the same run's path in the benchmark pose graph
// intel.g2o (built by others from the log) at its optimum. Intel has no relations file, so the
// check is the trajectory's deviation from that path (eval/PathDeviation.h): a wrong loop
// closure or a torn corridor puts poses metres off it, while the raw wheel odometry's drift is
// the baseline that shows the reference can tell.
#include <gtest/gtest.h>

#include <string>

#include "common/TestData.h"
#include "common/ToolRun.h"
#include "rtabmap_core/eval/PathDeviation.h"
#include "rtabmap_core/eval/Trajectory.h"

namespace rtabmap {
namespace {

TEST(IntelBenchmarkGraph, SlamFollowsTheOptimisedGraphsPathWhereWheelOdometryDrifts) {
  RTABMAP_REQUIRE_DATA(log, "radish/intel.clf.bz2");
  RTABMAP_REQUIRE_DATA(graph, "posegraphs/intel.g2o");
  test::TempDir dir("rtabmap_intel_graph");
  const std::string config = std::string(RTABMAP_CORE_SOURCE_DIR) + "/../config/lidar2d.ini";
  const test::ToolRun slam = test::runTool("dataset",
                                           "--format carmen --odom wheel --slam --max-frames 2500 --config " + config +
                                               " --output " + dir.file("out") + " --json " + log,
                                           dir);
  ASSERT_EQ(slam.exitCode, 0) << slam.stderrText;
  EXPECT_GT(test::lastJsonLine(slam.stdoutText)["proximity_links"].get<int>(), 100);
  const test::ToolRun g2o = test::runTool("g2o", graph + " " + dir.file("reference.g2o") + " --json", dir);
  ASSERT_EQ(g2o.exitCode, 0) << g2o.stderrText;
  const nlohmann::json optimum = test::lastJsonLine(g2o.stdoutText);
  ASSERT_TRUE(optimum["converged"].get<bool>());
  EXPECT_NEAR(optimum["final_chi2"].get<double>(), 45.0, 0.5);  // the graph's known optimum

  const Trajectory reference = readTrajectory(dir.file("reference.g2o"));
  const PathDeviationResult s = computePathDeviation(reference, readTrajectory(dir.file("out/frames.tum")));
  const PathDeviationResult w = computePathDeviation(reference, readTrajectory(dir.file("out/odom.tum")));
  EXPECT_EQ(s.estimatedPoses, 2500u);
  // Measured: SLAM median 0.047 m, p99 0.28, max 0.36; wheel odometry median 0.38, p99 5.9.
  // The reference path is a polyline through poses ~0.3 m apart, itself a map with its own
  // errors: a tenth of a metre at the median is agreement, half a metre anywhere is not.
  EXPECT_LT(s.stats.median, 0.1);
  EXPECT_LT(s.stats.max, 0.6);
  EXPECT_GT(w.p99, 2.0) << "the reference must tell the wheel odometry's drift from a map";
  EXPECT_GT(w.stats.median, 3.0 * s.stats.median);
}

}  // namespace
}  // namespace rtabmap
