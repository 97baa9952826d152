// Rtabmap's queries and edits for the ROS interface: planPath() (a plan that is not the goal),
// node() (a node's data from RAM or the database, only the parts asked), allNodeIds() and
// addLink() (a user link re-optimises the map at once, or is refused with a reason).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/TestData.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using Cov = Eigen::Matrix<double, 6, 6>;

Cov smallCov() { return Cov::Identity() * 1e-4; }  // 1 cm, 0.01 rad per motion

// A node with a small planar scan, so that the scan part of node() has something to carry.
SensorData frame(int id, double stamp) {
  cv::Mat points(1, 3, CV_32FC2);
  for (int i = 0; i < 3; ++i) points.at<cv::Vec2f>(0, i) = cv::Vec2f(1.0f + i, 0.5f * id);
  return SensorData(LaserScan(points, 3, 0.1, 10.0, LaserScan::kXY), id, stamp);
}

Transform along(double x, double yaw = 0.0) { return Transform(x, 0, 0, 0, 0, yaw); }

// Nodes 1..11 along x every 0.5 m (node i at 0.5 (i - 1)).
void corridor(Rtabmap& slam) {
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
}

bool hasLink(const std::multimap<int, Link>& links, int a, int b, Link::Type type) {
  return std::any_of(links.begin(), links.end(), [&](const auto& l) {
    const Link& k = l.second;
    return k.type() == type && ((k.from() == a && k.to() == b) || (k.from() == b && k.to() == a));
  });
}

TEST(RtabmapQueries, PlanPathDoesNotChangeTheGoal) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"}}, "");
  std::string why;
  EXPECT_TRUE(slam.planPath(1, &why).empty());
  EXPECT_NE(why.find("not in the map"), std::string::npos) << why;
  corridor(slam);
  ASSERT_TRUE(slam.setGoal(6)) << slam.lastRejection();

  const auto path = slam.planPath(2, &why);
  ASSERT_FALSE(path.empty()) << why;
  EXPECT_EQ(path.front().first, 11);
  EXPECT_EQ(path.back().first, 2);
  EXPECT_EQ(path.size(), 10u) << "every node from 11 back to 2";
  EXPECT_NEAR(path.back().second.x(), 0.5, 1e-6);
  ASSERT_FALSE(slam.goalPath().empty());
  EXPECT_EQ(slam.goalPath().back().first, 6) << "the active goal is untouched";

  // A pose goes to the nearest node.
  const auto toPose = slam.planPath(Transform(3.1, 0.2, 0, 0, 0, 0), &why);
  ASSERT_FALSE(toPose.empty()) << why;
  EXPECT_EQ(toPose.back().first, 7);

  EXPECT_TRUE(slam.planPath(999, &why).empty());
  EXPECT_NE(why.find("no path"), std::string::npos) << why;
  EXPECT_TRUE(slam.planPath(Transform(), &why).empty());
  EXPECT_NE(why.find("null"), std::string::npos) << why;
}

TEST(RtabmapQueries, NodeDataFromRamAndDatabaseWithTheAskedParts) {
  test::TempDir dir("rtabmap_queries_nodes");
  Rtabmap slam;
  // A small WM: the oldest nodes go to the database as the robot moves on.
  slam.init({{"Rtabmap/DetectionRate", "0"}, {"Rtabmap/MemoryThr", "3"}, {"Mem/STMSize", "2"},
             {"RGBD/LocalRadius", "0.6"}},
            dir.file("rtabmap.db"));
  corridor(slam);
  const std::vector<int> wm = slam.workingMemory();
  ASSERT_EQ(std::count(wm.begin(), wm.end(), 1), 0) << "node 1 should be in the database only";
  const std::vector<int> all = slam.allNodeIds();
  EXPECT_EQ(all, std::vector<int>({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));

  for (int id : {1, 11}) {  // from the database, from RAM
    SCOPED_TRACE("node " + std::to_string(id));
    const std::optional<Signature> full = slam.node(id);
    ASSERT_TRUE(full.has_value());
    EXPECT_EQ(full->id(), id);
    EXPECT_NEAR(full->getPose().x(), 0.5 * (id - 1), 1e-6) << "the odometry pose";
    const SensorData& d = full->sensorData();
    EXPECT_TRUE(!d.laserScanRaw().empty() || !d.laserScanCompressed().empty());
    EXPECT_FALSE(full->getLinks().empty()) << "links come with the node";

    NodeDataParts none;
    none.images = none.scan = none.grid = none.userData = false;
    const std::optional<Signature> bare = slam.node(id, none);
    ASSERT_TRUE(bare.has_value());
    EXPECT_TRUE(bare->sensorData().laserScanRaw().empty());
    EXPECT_TRUE(bare->sensorData().laserScanCompressed().empty());
    EXPECT_EQ(bare->getLinks().size(), full->getLinks().size());
  }
  EXPECT_FALSE(slam.node(999).has_value());
}

TEST(RtabmapQueries, UserLinkReoptimisesTheMapAtOnce) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"}}, "");
  corridor(slam);
  ASSERT_TRUE(slam.mapCorrection().isIdentity(1e-9));
  // The user measured node 11 at 4.9 m from node 1, not the 5 m of odometry: 1 cm per
  // odometry link (one standard deviation each), which the graph accepts.
  Link::InfMatrix information = Link::InfMatrix::Identity() * 1e4;
  ASSERT_TRUE(slam.addLink(Link(1, 11, Link::kUserClosure, along(4.9), information))) << slam.lastRejection();
  EXPECT_TRUE(hasLink(slam.allLinks(), 1, 11, Link::kUserClosure));
  const std::map<int, Transform> poses = slam.optimizedPoses();
  EXPECT_NEAR(poses.at(1).x(), 0.0, 1e-3) << "the oldest node stays";
  // Weighted by information: (1000 * 5.0 + 10000 * 4.9) / 11000 = 4.909 m.
  EXPECT_NEAR(poses.at(11).x(), 4.909, 0.005);
  EXPECT_LT(slam.mapCorrection().x(), -0.05) << "map -> odom follows the optimisation without waiting for an update";
  EXPECT_NEAR(slam.currentPose().x(), poses.at(11).x(), 1e-6);

  // A link the graph cannot hold: node 10 on top of node 2 (4 m off, with 1 cm uncertainty).
  EXPECT_FALSE(slam.addLink(Link(2, 10, Link::kUserClosure, Transform::Identity(), information)));
  EXPECT_NE(slam.lastRejection().find("OptimizeMaxError"), std::string::npos) << slam.lastRejection();
  EXPECT_FALSE(hasLink(slam.allLinks(), 2, 10, Link::kUserClosure)) << "a rejected link is undone";

  EXPECT_FALSE(slam.addLink(Link(3, 3, Link::kUserClosure, Transform::Identity())));
  EXPECT_NE(slam.lastRejection().find("two different"), std::string::npos);
  EXPECT_FALSE(slam.addLink(Link(3, 999, Link::kUserClosure, Transform::Identity())));
  EXPECT_NE(slam.lastRejection().find("999"), std::string::npos);
}

TEST(RtabmapQueries, UserLinkBringsBackNodesFromTheDatabaseAndIsSaved) {
  test::TempDir dir("rtabmap_queries_link");
  const std::string path = dir.file("rtabmap.db");
  {
    Rtabmap slam;
    slam.init({{"Rtabmap/DetectionRate", "0"}, {"Rtabmap/MemoryThr", "3"}, {"Mem/STMSize", "2"},
               {"RGBD/LocalRadius", "0.6"}},
              path);
    corridor(slam);
    const std::vector<int> wm = slam.workingMemory();
    ASSERT_EQ(std::count(wm.begin(), wm.end(), 1), 0);
    ASSERT_TRUE(slam.addLink(Link(1, 11, Link::kUserClosure, along(5.0), Link::InfMatrix::Identity() * 1e4)))
        << slam.lastRejection();
    slam.close();
  }
  Rtabmap slam;
  slam.init({{"Mem/IncrementalMemory", "false"}}, path);
  EXPECT_TRUE(hasLink(slam.allLinks(), 1, 11, Link::kUserClosure)) << "the link was saved";
  EXPECT_FALSE(slam.addLink(Link(1, 11, Link::kUserClosure, along(5.0))));
  EXPECT_NE(slam.lastRejection().find("localization"), std::string::npos) << slam.lastRejection();
}

}  // namespace
}  // namespace rtabmap
