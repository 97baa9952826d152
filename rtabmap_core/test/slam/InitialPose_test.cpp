// Rtabmap::setInitialPose() and the map a new session shows, on pose-only frames (no sensor:
// nothing can localise, so the poses are exactly what the start pose makes them).
#include <gtest/gtest.h>

#include <cmath>

#include "PoseOnlyFrames.h"
#include "common/TestData.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::along;
using test::everyFrame;
using test::frame;
using test::smallCov;

ParametersMap localization() { return {{"Rtabmap/DetectionRate", "0"}, {"Mem/IncrementalMemory", "false"}}; }

void expectNear(const Transform& a, const Transform& b, double tolerance = 1e-6) {
  ASSERT_FALSE(a.isNull());
  ASSERT_FALSE(b.isNull());
  EXPECT_LT((a.inverse() * b).getNorm(), tolerance) << a.prettyPrint() << " vs " << b.prettyPrint();
  EXPECT_LT(std::fabs((a.inverse() * b).getAngle()), tolerance) << a.prettyPrint() << " vs " << b.prettyPrint();
}

// A map of 5 nodes along x (0 to 2 m), saved in `path`.
void makeLine(const std::string& path) {
  Rtabmap slam;
  slam.init(everyFrame(), path);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
  slam.close();
}

TEST(InitialPose, LocalizationStartsThereInsteadOfAtTheLastPose) {
  test::TempDir dir("rtabmap_initial_pose_loc");
  const std::string path = dir.file("rtabmap.db");
  makeLine(path);
  // The robot restarts with odometry of its own (not at identity) somewhere else in the map.
  const Transform odom0(3.0, -1.0, 0.0, 0.0, 0.0, 0.7);
  const Transform odom1 = odom0 * along(0.4, 0.1);
  {
    // Without a pose from the user: where the last session ended (node 5, x = 2).
    Rtabmap slam;
    slam.init(localization(), path);
    slam.process(frame(10, 10.0), odom0, smallCov());
    EXPECT_TRUE(slam.lastRejection().empty()) << slam.lastRejection();
    expectNear(slam.currentPose(), along(2.0));
  }
  Rtabmap slam;
  slam.init(localization(), path);
  const Transform given(-4.0, 6.0, 0.0, 0.0, 0.0, -2.0);
  std::string why = "stale";
  ASSERT_TRUE(slam.setInitialPose(given, &why));
  EXPECT_TRUE(why.empty());
  slam.process(frame(10, 10.0), odom0, smallCov());
  EXPECT_TRUE(slam.lastRejection().empty()) << slam.lastRejection();
  expectNear(slam.mapCorrection(), given * odom0.inverse());
  expectNear(slam.currentPose(), given);
  // Then the robot moves with its odometry from there.
  slam.process(frame(11, 11.0), odom1, smallCov());
  expectNear(slam.currentPose(), given * along(0.4, 0.1));
  EXPECT_EQ(slam.summary().nodesAdded, 0);

  // Given again while running: map -> odom moves at once with the last odometry pose.
  const Transform again(1.0, 1.0, 0.0, 0.0, 0.0, 0.3);
  ASSERT_TRUE(slam.setInitialPose(again));
  expectNear(slam.mapCorrection(), again * odom1.inverse());
  expectNear(slam.currentPose(), again);
  const Transform odom2 = odom1 * along(0.2);
  slam.process(frame(12, 12.0), odom2, smallCov());
  expectNear(slam.currentPose(), again * along(0.2));
}

TEST(InitialPose, ProjectedOnThePlaneWithForce3DoF) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"}, {"Reg/Force3DoF", "true"}}, "");
  ASSERT_TRUE(slam.setInitialPose(Transform(1.0, 2.0, 0.5, 0.2, -0.1, 1.0)));
  ASSERT_TRUE(slam.process(frame(1, 1.0), along(0.0), smallCov()));
  expectNear(slam.currentPose(), Transform(1.0, 2.0, 0.0, 0.0, 0.0, 1.0));
}

TEST(InitialPose, MappingPlacesANewMapBeforeItsFirstNodeOnly) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  const Transform start(5.0, -2.0, 0.0, 0.0, 0.0, M_PI / 2);
  ASSERT_TRUE(slam.setInitialPose(start));
  ASSERT_TRUE(slam.process(frame(1, 1.0), along(1.0), smallCov()));
  ASSERT_TRUE(slam.process(frame(2, 2.0), along(2.0), smallCov()));
  const std::map<int, Transform> poses = slam.optimizedPoses();
  ASSERT_EQ(poses.size(), 2u);
  expectNear(poses.begin()->second, start);
  expectNear(poses.rbegin()->second, start * along(1.0));

  // The map has nodes: moving the robot would tear it.
  std::string why;
  EXPECT_FALSE(slam.setInitialPose(Transform(0, 0, 0, 0, 0, 0), &why));
  EXPECT_NE(why.find("already has nodes"), std::string::npos) << why;
  expectNear(slam.currentPose(), start * along(1.0));

  // A new map may start anywhere.
  slam.triggerNewMap();
  const Transform second(-3.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  ASSERT_TRUE(slam.setInitialPose(second, &why)) << why;
  ASSERT_TRUE(slam.process(frame(3, 3.0), along(3.0), smallCov()));
  expectNear(slam.currentPose(), second);
  EXPECT_EQ(slam.optimizedPoses().size(), 1u);
}

TEST(InitialPose, RefusesBadPosesWithAReason) {
  Rtabmap idle;
  std::string why;
  EXPECT_FALSE(idle.setInitialPose(Transform::Identity(), &why));
  EXPECT_NE(why.find("init"), std::string::npos) << why;

  Rtabmap slam;
  slam.init(everyFrame(), "");
  EXPECT_FALSE(slam.setInitialPose(Transform(), &why));
  EXPECT_NE(why.find("null"), std::string::npos) << why;
  EXPECT_FALSE(slam.setInitialPose(Transform(NAN, 0, 0, 0, 0, 0), &why));
  EXPECT_NE(why.find("finite"), std::string::npos) << why;
  // Nothing was kept from the refused poses: the map starts at the origin.
  ASSERT_TRUE(slam.process(frame(1, 1.0), along(1.0), smallCov()));
  expectNear(slam.currentPose(), along(1.0));

  Rtabmap topological;
  topological.init({{"RGBD/Enabled", "false"}}, "");
  EXPECT_FALSE(topological.setInitialPose(Transform::Identity(), &why));
  EXPECT_NE(why.find("RGBD/Enabled"), std::string::npos) << why;
}

// get_map_data right after a new session starts: the map of the database, not the new map's
// nothing; then the new map alone (not linked to the old one) once it has a node.
TEST(InitialPose, NewSessionShowsThePreviousMapUntilItsFirstNode) {
  test::TempDir dir("rtabmap_initial_pose_session");
  const std::string path = dir.file("rtabmap.db");
  makeLine(path);
  {
    Rtabmap slam;
    slam.init(everyFrame(), path);
    const std::map<int, Transform> before = slam.optimizedPoses();
    ASSERT_EQ(before.size(), 5u);
    expectNear(before.rbegin()->second, along(2.0));
    ASSERT_TRUE(slam.process(frame(10, 10.0), along(0.0), smallCov()));
    EXPECT_EQ(slam.optimizedPoses().size(), 1u);
    slam.close();
  }
  {
    // A session that adds no node (opened and closed, a backup) leaves a map id without a map.
    Rtabmap empty;
    empty.init(everyFrame(), path);
    empty.close();
  }
  // Localization works on the newest nodes' map, not on that empty one: it shows the map, and
  // starts at its last pose.
  Rtabmap slam;
  slam.init(localization(), path);
  const std::map<int, Transform> shown = slam.optimizedPoses();
  ASSERT_EQ(shown.size(), 1u) << "the second session's map (one node, not linked to the first)";
  slam.process(frame(20, 20.0), along(7.0), smallCov());
  EXPECT_TRUE(slam.lastRejection().empty()) << slam.lastRejection();
  expectNear(slam.currentPose(), shown.rbegin()->second);
}

}  // namespace
}  // namespace rtabmap
