// rtabmap-g2o: the --json contract, the output file, and errors on bad files.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

#include "SyntheticGraph.h"
#include "common/TestData.h"
#include "common/ToolRun.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap {
namespace {

using test::lastJsonLine;
using test::ToolRun;

ToolRun runG2o(const std::string& arguments, const test::TempDir& dir) { return test::runTool("g2o", arguments, dir); }

TEST(G2oTool, OptimisesWritesAndReportsJson) {
  test::TempDir dir;
  test::NoiseModel noise;
  const auto g = test::makeSquareLoops(2, 5, false, noise, 201, 0, 0.5);
  const std::string input = dir.file("in.g2o");
  graph::writeG2o(input, g.odometry, g.links, false);
  const std::string output = dir.file("out.g2o");

  const ToolRun run = runG2o("--json " + input + " " + output, dir);
  ASSERT_EQ(run.exitCode, 0) << run.stdoutText << run.stderrText;
  const nlohmann::json j = lastJsonLine(run.stdoutText);
  EXPECT_EQ(j["poses"], g.odometry.size());
  EXPECT_EQ(j["edges"], g.links.size());
  EXPECT_EQ(j["graph"], "SE3");
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_TRUE(j["success"].get<bool>());
  EXPECT_EQ(j["root"], 0);  // the first vertex, as g2o does
  EXPECT_EQ(j["init"], "chordal");
  EXPECT_GT(j["iterations"].get<int>(), 0);
  EXPECT_GT(j["time_s"].get<double>(), 0.0);
  EXPECT_GE(j["cpu_time_s"].get<double>(), 0.0);
  EXPECT_LT(j["final_chi2"].get<double>(), j["initial_chi2"].get<double>() + 1e-9);

  // The output file holds the optimised graph, whose chi2 is the one reported.
  const graph::PoseGraphFile out = graph::readG2o(output);
  EXPECT_EQ(out.poses.size(), g.odometry.size());
  EXPECT_NEAR(graph::computeChi2(out.poses, out.links, false), j["final_chi2"].get<double>(),
              1e-6 * j["final_chi2"].get<double>());
}

TEST(G2oTool, OptionsChangeTheRun) {
  test::TempDir dir;
  const auto g = test::makeSquareLoops(2, 5, true, test::NoiseModel(), 202, 0);
  const std::string input = dir.file("in.g2o");
  graph::writeG2o(input, g.odometry, g.links, true);
  const ToolRun run =
      runG2o("--json --init odometry --iterations 1 --root 7 --threads 2 " + input, dir);
  ASSERT_EQ(run.exitCode, 0) << run.stderrText;
  const nlohmann::json j = lastJsonLine(run.stdoutText);
  EXPECT_EQ(j["graph"], "SE2");
  EXPECT_EQ(j["init"], "input");
  EXPECT_EQ(j["root"], 7);
  EXPECT_EQ(j["threads"], 2);
  EXPECT_LE(j["iterations"].get<int>(), 1);
  // Core parameters work too.
  const ToolRun tree = runG2o("--json --Optimizer/Init 1 " + input, dir);
  ASSERT_EQ(tree.exitCode, 0) << tree.stderrText;
  EXPECT_EQ(lastJsonLine(tree.stdoutText)["init"], "tree");
  // A wrong option value is a usage error.
  EXPECT_EQ(runG2o("--init best " + input, dir).exitCode, 2);
}

TEST(G2oTool, BadFilesFailNamingTheLine) {
  test::TempDir dir;
  const std::string input = dir.file("bad.g2o");
  {
    std::ofstream out(input);
    out << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 nan 1 0 0 1 0 1\n";
  }
  const ToolRun run = runG2o("--json " + input, dir);
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.stderrText.find(input + ":3:"), std::string::npos) << run.stderrText;
  EXPECT_NE(run.stderrText.find("NaN"), std::string::npos) << run.stderrText;
  EXPECT_EQ(runG2o(dir.file("missing.g2o"), dir).exitCode, 1);
}

TEST(G2oTool, IntelReachesTheBestKnownChi2) {
  RTABMAP_REQUIRE_DATA(intel, "posegraphs/intel.g2o");
  test::TempDir dir;
  const ToolRun run = runG2o("--json " + intel, dir);
  ASSERT_EQ(run.exitCode, 0) << run.stderrText;
  const nlohmann::json j = lastJsonLine(run.stdoutText);
  EXPECT_EQ(j["poses"], 1728);
  EXPECT_EQ(j["edges"], 2512);
  EXPECT_LT(j["final_chi2"].get<double>(), 45.0047 * 1.01);
}

}  // namespace
}  // namespace rtabmap
