// Rejecting wrong loop closures after optimisation (RGBD/OptimizeMaxError).
#include <gtest/gtest.h>

#include <cmath>

#include "SyntheticGraph.h"
#include "rtabmap_core/optimizer/LinkErrors.h"
#include "rtabmap_core/optimizer/Optimizer.h"

namespace rtabmap {
namespace {

using test::makeSquareLoops;
using test::NoiseModel;

TEST(LinkErrors, AWrongLoopClosureIsFlaggedAndTheGoodOnesAreNot) {
  NoiseModel noise;
  noise.sigmaXY = 0.02;
  noise.sigmaAngle = 0.005;
  for (bool is2D : {true, false}) {
    const auto g = makeSquareLoops(2, 8, is2D, noise, 91, 1, 0.4);
    OptimizerOptions options;
    options.force3DoF = is2D;

    // Without the wrong link: no link over 3 standard deviations.
    OptimizerSummary summary;
    auto optimized = optimizeGraph(options, g.odometry, g.links, &summary);
    ASSERT_TRUE(summary.success) << summary.why;
    graph::MaxErrorCheck check = graph::checkMaxLinkError(optimized, g.links, 3.0, is2D);
    EXPECT_FALSE(check.rejected) << check.why;
    EXPECT_EQ(check.linksChecked, 32);  // the loop closures of lap 2
    EXPECT_TRUE(check.why.empty());
    EXPECT_LT(check.worstTranslational.translationalRatio(), 3.0);

    // Add a loop closure 5 m off.
    auto links = g.links;
    const Transform wrong = g.truth.at(45).inverse() * g.truth.at(10) * Transform(5, 0, 0, 0, 0, 0);
    links.emplace(45, Link(45, 10, Link::kGlobalClosure, wrong, test::informationOf(noise, is2D)));
    optimized = optimizeGraph(options, g.odometry, links, &summary);
    ASSERT_TRUE(summary.success) << summary.why;
    check = graph::checkMaxLinkError(optimized, links, 3.0, is2D);
    EXPECT_TRUE(check.rejected);
    ASSERT_FALSE(check.offending.empty());
    EXPECT_EQ(check.offending.front().from, 45);
    EXPECT_EQ(check.offending.front().to, 10);
    EXPECT_EQ(check.worstTranslational.from, 45);
    EXPECT_GT(check.worstTranslational.translationalRatio(), 10.0);
    EXPECT_NE(check.why.find("45->10"), std::string::npos) << check.why;
    EXPECT_NE(check.why.find("GlobalClosure"), std::string::npos) << check.why;

    // 0 disables the check.
    EXPECT_FALSE(graph::checkMaxLinkError(optimized, links, 0.0, is2D).rejected);
  }
}

TEST(LinkErrors, RatiosByHand) {
  // Optimised relative pose (1, 0, 0) against a measurement (1.3, 0.4, 0.1): error 0.5 m,
  // 0.1 rad. Standard deviations: the largest variance of x/y (0.04 -> 0.2 m) and yaw
  // (0.0025 -> 0.05 rad): ratios 2.5 and 2.
  std::map<int, Transform> poses{{1, Transform(0, 0, 0)}, {2, Transform(1, 0, 0)}};
  Link::InfMatrix info = Link::InfMatrix::Identity();
  info(0, 0) = 100;  // variance 0.01
  info(1, 1) = 25;   // variance 0.04
  info(5, 5) = 400;  // variance 0.0025
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kLocalSpaceClosure, Transform(1.3, 0.4, 0.1), info));
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(2, 0, 0), info));  // not checked
  const auto errors = graph::computeLinkErrors(poses, links, true);
  ASSERT_EQ(errors.size(), 1u);
  // E = Z^-1 * D: |t_E| = |(-0.3, -0.4)| = 0.5, angle 0.1.
  EXPECT_NEAR(errors[0].translationalError, 0.5, 1e-12);
  EXPECT_NEAR(errors[0].angularError, 0.1, 1e-12);
  EXPECT_NEAR(errors[0].translationalStd, 0.2, 1e-12);
  EXPECT_NEAR(errors[0].angularStd, 0.05, 1e-12);
  EXPECT_NEAR(errors[0].translationalRatio(), 2.5, 1e-9);
  EXPECT_NEAR(errors[0].angularRatio(), 2.0, 1e-9);

  EXPECT_FALSE(graph::checkMaxLinkError(poses, links, 3.0, true).rejected);
  const auto check = graph::checkMaxLinkError(poses, links, 2.2, true);
  EXPECT_TRUE(check.rejected);
  EXPECT_NE(check.why.find("translational"), std::string::npos) << check.why;
  // Every relative link when asked.
  EXPECT_EQ(graph::computeLinkErrors(poses, links, true, false).size(), 2u);
}

}  // namespace
}  // namespace rtabmap
