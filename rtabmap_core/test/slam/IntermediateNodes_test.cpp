// Rtabmap/CreateIntermediateNodes: the frames Rtabmap/DetectionRate skips still become nodes of
// the graph (weight -1, no detection), so the optimised graph holds the whole trajectory.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "LidarRobot.h"
#include "PoseOnlyFrames.h"
#include "common/TestData.h"
#include "registration/IcpTestScenes.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::along;
using test::smallCov;

ParametersMap withIntermediateNodes(bool dataKept = false) {
  return {{"Rtabmap/DetectionRate", "1"},
          {"Rtabmap/CreateIntermediateNodes", "true"},
          {"Mem/IntermediateNodeDataKept", dataKept ? "true" : "false"}};
}

// A frame with a small 2D scan (a wall 2 m ahead), stamped `stamp`.
SensorData scanFrame(int id, double stamp) {
  cv::Mat points(1, 20, CV_32FC2);
  for (int i = 0; i < 20; ++i) points.at<cv::Vec2f>(0, i) = cv::Vec2f(2.f, -1.f + 0.1f * static_cast<float>(i));
  return SensorData(LaserScan(points, 20, 0.1, 10.0, LaserScan::kXY), id, stamp);
}

TEST(IntermediateNodes, SkippedFramesBecomeNodesOfTheTrajectory) {
  Rtabmap slam;
  slam.init(withIntermediateNodes(), "");
  // 10 Hz at 1.2 m/s for 3 s, then 1 s still: updates at 1 Hz, every moving frame a node.
  int updates = 0;
  for (int i = 0; i <= 40; ++i) {
    const double x = 0.12 * std::min(i, 30);
    if (slam.process(test::frame(i + 1, 10.0 + 0.1 * i), along(x), smallCov())) ++updates;
  }
  EXPECT_EQ(updates, 4);  // 10.0, 11.0, 12.0, 13.0 (14.0: still)
  EXPECT_EQ(slam.summary().nodesAdded, 4);
  EXPECT_EQ(slam.summary().intermediateNodes, 27);  // the moving frames between (none once still)
  const std::map<int, Transform> poses = slam.optimizedPoses();
  ASSERT_EQ(poses.size(), 31u);
  int intermediate = 0;
  for (const auto& [id, pose] : poses) {
    const std::optional<Signature> s = slam.node(id);
    ASSERT_TRUE(s.has_value()) << id;
    intermediate += s->isIntermediate() ? 1 : 0;
    EXPECT_NEAR(pose.x(), s->getPose().x(), 1e-9) << id;  // the odometry: nothing closed a loop
    if (s->isIntermediate()) {
      EXPECT_TRUE(s->getWords().empty());
      EXPECT_TRUE(s->sensorData().laserScanRaw().empty() && s->sensorData().laserScanCompressed().empty());
    }
  }
  EXPECT_EQ(intermediate, 27);
  // One chain of neighbour links through every node, each the odometry between them.
  int neighbors = 0;
  for (const auto& [from, link] : slam.localLinks()) {
    if (link.type() != Link::kNeighbor) continue;
    ++neighbors;
    EXPECT_NEAR(link.transform().x(), poses.at(link.to()).x() - poses.at(link.from()).x(), 1e-9);
  }
  EXPECT_EQ(neighbors, 30);
}

TEST(IntermediateNodes, NoneInLocalizationModeNorWhenOff) {
  Rtabmap off;
  off.init({{"Rtabmap/DetectionRate", "1"}}, "");
  for (int i = 0; i < 15; ++i) off.process(test::frame(i + 1, 10.0 + 0.1 * i), along(0.12 * i), smallCov());
  EXPECT_EQ(off.summary().intermediateNodes, 0);
  EXPECT_EQ(off.optimizedPoses().size(), 2u);

  rtabmap::test::TempDir dir;
  const std::string path = dir.file("map.db");
  {
    Rtabmap mapping;
    mapping.init(withIntermediateNodes(), path);
    for (int i = 0; i < 15; ++i) mapping.process(test::frame(i + 1, 10.0 + 0.1 * i), along(0.12 * i), smallCov());
    EXPECT_EQ(mapping.summary().intermediateNodes, 13);
    mapping.close();
  }
  ParametersMap localization = withIntermediateNodes();
  localization["Mem/IncrementalMemory"] = "false";
  Rtabmap loc;
  loc.init(localization, path);
  for (int i = 0; i < 15; ++i) loc.process(test::frame(100 + i, 20.0 + 0.1 * i), along(0.12 * i), smallCov());
  EXPECT_EQ(loc.summary().intermediateNodes, 0);
}

// The reason for them: a loop closure corrects the whole trajectory, not only the nodes at the
// detection rate. Out 3.6 m and back with odometry 5% long on the way out (back at 0.18 m from
// the start), then the user closes the loop.
TEST(IntermediateNodes, ALoopClosureCorrectsThemWithTheRest) {
  Rtabmap slam;
  slam.init(withIntermediateNodes(), "");
  std::map<double, Transform> truth;  // by stamp
  for (int i = 0; i <= 60; ++i) {
    const double s = 0.12 * i;                    // distance travelled
    const double x = s <= 3.6 ? s : 7.2 - s;      // true position
    const double yaw = s <= 3.6 ? 0.0 : M_PI;
    const double stamp = 10.0 + 0.1 * i;
    truth[stamp] = Transform(x, 0, 0, 0, 0, yaw);
    const double ox = s <= 3.6 ? 1.05 * s : 1.05 * 3.6 - (s - 3.6);
    slam.process(test::frame(i + 1, stamp), Transform(ox, 0, 0, 0, 0, yaw), smallCov());
  }
  ASSERT_GT(slam.summary().intermediateNodes, 40);
  const auto error = [&](bool intermediateOnly) {
    double sum = 0.0;
    int n = 0;
    for (const auto& [id, pose] : slam.optimizedPoses()) {
      const std::optional<Signature> s = slam.node(id);
      if (!s || (intermediateOnly && !s->isIntermediate())) continue;
      const Transform& t = truth.at(s->stamp());
      sum += std::hypot(pose.x() - t.x(), pose.y() - t.y());
      ++n;
    }
    return sum / n;
  };
  const double before = error(true);
  // The last node is back at the start, facing the other way.
  const int first = slam.optimizedPoses().begin()->first;
  const Link closure(slam.lastNodeId(), first, Link::kUserClosure, Transform(0, 0, 0, 0, 0, M_PI),
                     Link::InfMatrix::Identity() * 1e4);
  ASSERT_TRUE(slam.addLink(closure)) << slam.lastRejection();
  const double after = error(true);
  EXPECT_GT(before, 0.08);
  EXPECT_LT(after, 0.5 * before) << "mean error of the intermediate nodes " << before << " -> " << after << " m";
}

TEST(IntermediateNodes, TheirDataIsKeptOnlyWhenAsked) {
  for (bool kept : {false, true}) {
    rtabmap::test::TempDir dir;
    const std::string path = dir.file("map.db");
    int intermediateId = 0;
    {
      Rtabmap slam;
      slam.init(withIntermediateNodes(kept), path);
      for (int i = 0; i < 12; ++i) slam.process(scanFrame(i + 1, 10.0 + 0.1 * i), along(0.12 * i), smallCov());
      for (const auto& [id, pose] : slam.optimizedPoses()) {
        if (slam.node(id)->isIntermediate()) intermediateId = id;
      }
      slam.close();
    }
    ASSERT_NE(intermediateId, 0);
    db::DatabaseOptions readOnly;
    readOnly.readOnly = true;
    db::Database database(path, readOnly);
    const std::optional<Signature> s = database.loadNode(intermediateId);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->weight(), -1);
    EXPECT_EQ(!s->sensorData().laserScanCompressed().empty(), kept) << "kept " << kept;
    EXPECT_GT(s->stamp(), 10.0);
    EXPECT_TRUE(s->getWords().empty());
    EXPECT_TRUE(s->sensorData().localGrid().isEmpty());
    // 12 frames at 10 Hz: nodes at 10.0 and 11.0, the 10 others between.
    EXPECT_EQ(database.summary().intermediateNodes, 10);
    EXPECT_EQ(database.summary().nodes, 12);
  }
}

// RGBD/NeighborLinkRefining registers a new node with the node before the intermediate nodes
// (they have no scan) and spreads the correction over them: the whole chain follows the scans,
// not only the nodes at the detection rate. Wheel odometry 15% long, in the office.
TEST(IntermediateNodes, NeighbourLinkRefiningCorrectsTheChainBetweenTwoNodes) {
  ParametersMap p = test::lidarRobot();
  for (const auto& [k, v] : withIntermediateNodes()) p[k] = v;
  p[Parameters::kIcpMaxTranslation()] = "2";  // 1.1 m between updates
  const test::World2D world = test::officeWorld();
  test::Lidar2D lidar;
  lidar.rangeMax = 8.0;
  lidar.noise = 0.005;
  std::mt19937 rng(test::drawSeed(11));
  const Transform start(1.5, 6.0, 0.0, 0.0, 0.0, 0.0);
  const Transform step(0.11, 0.0, 0.0, 0.0, 0.0, 0.01);           // true motion per frame (10 Hz)
  const Transform odomStep(0.1265, 0.0, 0.0, 0.0, 0.0, 0.0115);   // what the wheels say
  Rtabmap slam;
  slam.init(p, "");
  std::map<double, Transform> truth, odometry;  // by stamp, relative to the start
  Transform t = Transform::Identity(), o = Transform::Identity();
  for (int i = 0; i <= 20; ++i) {
    const double stamp = 1.0 + 0.1 * i;
    truth[stamp] = t;
    odometry[stamp] = o;
    slam.process(SensorData(test::castScan2D(world, start * t, lidar, &rng), i + 1, stamp), start * o,
                 smallCov());
    t = t * step;
    o = o * odomStep;
  }
  ASSERT_EQ(slam.summary().nodesAdded, 3);
  ASSERT_EQ(slam.summary().intermediateNodes, 18);
  const std::map<int, Transform> poses = slam.optimizedPoses();
  const Transform first = poses.begin()->second;
  double worstOdometry = 0.0, worstGraph = 0.0;
  for (const auto& [id, pose] : poses) {
    const double stamp = slam.node(id)->stamp();
    const Transform graph = first.inverse() * pose;
    worstGraph = std::max(worstGraph, (truth.at(stamp).inverse() * graph).getNorm());
    worstOdometry = std::max(worstOdometry, (truth.at(stamp).inverse() * odometry.at(stamp)).getNorm());
  }
  EXPECT_GT(worstOdometry, 0.3);
  EXPECT_LT(worstGraph, 0.02) << "worst node of the chain off by " << worstGraph << " m (odometry: " << worstOdometry << ")";
}

}  // namespace
}  // namespace rtabmap
