// The reference pose graphs of ../shared/data/posegraphs reach their best known g2o chi2
// (data README) within 1% with default options. The large ones (city10000, sphere2500) are
// left to bench-optimizer_bench; these take well under a second each.
#include <gtest/gtest.h>

#include <ostream>

#include "common/TestData.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap {
namespace {

struct Reference {
  const char* file;
  double bestChi2;
};
// Test listings (and ctest names) show the file instead of the struct's bytes.
void PrintTo(const Reference& ref, std::ostream* os) { *os << ref.file; }

class ReferenceGraphs : public ::testing::TestWithParam<Reference> {};

TEST_P(ReferenceGraphs, ReachTheBestKnownChi2WithinOnePercent) {
  const Reference ref = GetParam();
  RTABMAP_REQUIRE_DATA(path, std::string("posegraphs/") + ref.file);
  const graph::PoseGraphFile file = graph::readG2o(path);
  OptimizerOptions options = OptimizerOptions::fromParameters({});
  options.force3DoF = file.is2D;
  OptimizerSummary summary;
  const auto optimized =
      optimizeGraph(options, file.poses, file.links, &summary, file.poses.begin()->first);
  ASSERT_TRUE(summary.success) << summary.why;
  EXPECT_TRUE(summary.converged) << summary.why;
  EXPECT_EQ(optimized.size(), file.poses.size());
  EXPECT_LT(summary.finalChi2, ref.bestChi2 * 1.01) << ref.file;
  EXPECT_GT(summary.finalChi2, ref.bestChi2 * 0.99) << ref.file;  // a lower value would be a bug
  // The summary's chi2 is the one of the returned poses.
  EXPECT_NEAR(graph::computeChi2(optimized, file.links, file.is2D), summary.finalChi2,
              1e-6 * summary.finalChi2);
}

INSTANTIATE_TEST_SUITE_P(Optimizer, ReferenceGraphs,
                         ::testing::Values(Reference{"intel.g2o", 45.0047},
                                           Reference{"manhattan.g2o", 3549.04},
                                           Reference{"kitti_00.g2o", 98.322},
                                           Reference{"parking-garage.g2o", 1.23869}),
                         [](const ::testing::TestParamInfo<Reference>& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

TEST(ReferenceGraphsInit, TreeAndOdometryInitialisationAlsoReachTheOptimumOnManhattan) {
  // M3500 has no vertices: odometry initialisation composes the consecutive edges.
  RTABMAP_REQUIRE_DATA(path, "posegraphs/manhattan.g2o");
  const graph::PoseGraphFile file = graph::readG2o(path);
  for (GraphInitialization init : {GraphInitialization::kSpanningTree, GraphInitialization::kInputPoses}) {
    OptimizerOptions options;
    options.force3DoF = true;
    options.initialization = init;
    OptimizerSummary summary;
    optimizeGraph(options, file.poses, file.links, &summary, 0);
    ASSERT_TRUE(summary.success) << summary.why;
    EXPECT_LT(summary.finalChi2, 3549.04 * 1.01) << initializationName(init);
  }
}

}  // namespace
}  // namespace rtabmap
