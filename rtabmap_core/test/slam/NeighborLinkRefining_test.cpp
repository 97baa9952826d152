// RGBD/NeighborLinkRefining: the refined odometry link carries what the scans measured, so the
// graph weighs it consistently with the proximity links that close loops (issue 8: with the
// wheel odometry's isotropic, stiff information kept on ICP links, proximity links were
// negligible, loops stayed open on ACES and corridors bent on Intel).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "LidarRobot.h"
#include "common/TestData.h"
#include "registration/IcpTestScenes.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using Cov = Eigen::Matrix<double, 6, 6>;
using test::lidarRobot;

// The refined link between the robot's two nodes, after driving `step` along `world`.
Link refinedLink(const test::World2D& world, const Transform& start, const Transform& step,
                 const ParametersMap& parameters = lidarRobot()) {
  test::TempDir dir;
  Rtabmap slam;
  slam.init(parameters, dir.path() + "/map.db");
  test::Lidar2D lidar;
  lidar.rangeMax = 8.0;
  lidar.noise = 0.005;
  std::mt19937 rng(test::drawSeed(7));
  // Wheel odometry: isotropic 1 cm / 0.01 rad, a little off the true motion.
  const Cov wheel = Cov::Identity() * 1e-4;
  const Transform odomError(0.02, -0.01, 0.0, 0.0, 0.0, 0.01);
  const Transform end = start * step;
  EXPECT_TRUE(slam.process(SensorData(test::castScan2D(world, start, lidar, &rng), 1, 1.0), start, wheel))
      << slam.lastRejection();
  EXPECT_TRUE(slam.process(SensorData(test::castScan2D(world, end, lidar, &rng), 2, 2.0), end * odomError, wheel))
      << slam.lastRejection();
  for (const auto& [from, link] : slam.allLinks()) {
    if (link.type() == Link::kNeighbor && link.from() < link.to()) return link;
  }
  ADD_FAILURE() << "no neighbour link";
  return Link();
}

TEST(NeighborLinkRefining, CorridorLinkIsStiffAcrossAndFreeAlong) {
  // A long corridor along x: ICP pins the lateral offset and the heading, nothing along x.
  const Link link = refinedLink(test::corridorWorld(), Transform(0.0, 0.1, 0.0), Transform(0.3, 0.0, 0.0));
  const Link::InfMatrix& inf = link.infMatrix();
  // The wheel odometry said 1e4 in every direction; the scans say otherwise.
  EXPECT_GT(inf(1, 1), 100.0 * inf(0, 0)) << inf.diagonal().transpose();
  EXPECT_LT(inf(0, 0), 1e3) << "along the corridor the link knows nothing: it must yield to loop closures";
  // Not the wheels' isotropic weight: the graph can slide the corridor along its axis to close a
  // loop, rather than bend it.
  EXPECT_NE(inf(1, 1), 1e4);
  // And the transform is the scans' across the corridor (the odometry's 1 cm lateral error removed).
  EXPECT_NEAR(link.transform().y(), 0.0, 5e-3);
}

TEST(NeighborLinkRefining, RoomLinkIsConstrainedInEveryDirection) {
  const Link link = refinedLink(test::officeWorld(), Transform(4.0, 6.0, 0.3), Transform(0.25, -0.05, 0.0, 0, 0, 0.05));
  const Link::InfMatrix& inf = link.infMatrix();
  EXPECT_GT(inf(0, 0), 1e3) << inf.diagonal().transpose();
  EXPECT_GT(inf(1, 1), 1e3) << inf.diagonal().transpose();
  EXPECT_GT(inf(5, 5), 1e3) << inf.diagonal().transpose();
  const Transform truth(0.25, -0.05, 0.0, 0, 0, 0.05);
  EXPECT_LT((truth.inverse() * link.transform()).getNorm(), 0.01);
}

// Reg/Strategy 2 (visual then ICP): where the images do not match (a turn; here no image at
// all) the visual step fails, and ICP alone refines the link from the odometry.
TEST(NeighborLinkRefining, VisualThenIcpFallsBackToIcpFromTheOdometry) {
  ParametersMap p = lidarRobot();
  p[Parameters::kRegStrategy()] = "2";
  p[Parameters::kKpMaxFeatures()] = "-1";
  const Transform truth(0.25, -0.05, 0.0, 0, 0, 0.05);
  const Link link = refinedLink(test::officeWorld(), Transform(4.0, 6.0, 0.3), truth, p);
  EXPECT_LT((truth.inverse() * link.transform()).getNorm(), 0.01) << link.transform().prettyPrint();
  EXPECT_NE(link.infMatrix()(0, 0), 1e4) << "the wheel odometry's link was kept";
}

}  // namespace
}  // namespace rtabmap
