// Rtabmap::process() on synthetic input: what it refuses and why, when it adds nodes, sessions,
// labels, and what survives a restart on the same database.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "PoseOnlyFrames.h"
#include "common/HeapHoles.h"
#include "common/TestData.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/ProcessMemory.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::along;
using test::Cov;
using test::everyFrame;
using test::frame;
using test::smallCov;

TEST(Rtabmap, RefusesBadOdometryWithAReason) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  EXPECT_FALSE(slam.process(frame(1, 1.0), Transform(), smallCov()));
  EXPECT_NE(slam.lastRejection().find("null"), std::string::npos) << slam.lastRejection();
  EXPECT_FALSE(slam.process(frame(2, 2.0), Transform(NAN, 0, 0, 0, 0, 0), smallCov()));
  EXPECT_NE(slam.lastRejection().find("finite"), std::string::npos) << slam.lastRejection();
  EXPECT_FALSE(slam.process(frame(3, 3.0), along(1.0), Cov::Identity() * 9999.0));
  EXPECT_NE(slam.lastRejection().find("lost"), std::string::npos) << slam.lastRejection();
  EXPECT_EQ(slam.summary().nodesAdded, 0);
  EXPECT_EQ(slam.summary().refused, 3);
  // Odometry back: the map starts.
  EXPECT_TRUE(slam.process(frame(4, 4.0), along(1.0), smallCov()));
  EXPECT_TRUE(slam.lastRejection().empty());
  EXPECT_EQ(slam.summary().nodesAdded, 1);
}

TEST(Rtabmap, PoseOnlyNodesMakeAGraphFollowingOdometry) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
  EXPECT_EQ(slam.summary().nodesAdded, 5);
  const std::map<int, Transform> poses = slam.optimizedPoses();
  ASSERT_EQ(poses.size(), 5u);
  EXPECT_NEAR(poses.rbegin()->second.x(), 2.0, 1e-9);
  EXPECT_TRUE(slam.mapCorrection().isIdentity(1e-9));
  // Neighbour links carry the odometry motion.
  int neighbors = 0;
  for (const auto& [from, link] : slam.localLinks()) {
    if (link.type() != Link::kNeighbor) continue;
    ++neighbors;
    EXPECT_NEAR(link.transform().x(), 0.5, 1e-9);
  }
  EXPECT_EQ(neighbors, 4);
}

TEST(Rtabmap, NoUpdateWhileTheRobotMovesFasterThanTheSpeedLimits) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "1"}, {"RGBD/LinearSpeedUpdate", "0.5"}, {"RGBD/AngularSpeedUpdate", "0.4"}}, "");
  ASSERT_TRUE(slam.process(frame(1, 10.0), along(0.0), smallCov()));
  EXPECT_TRUE(slam.process(frame(2, 11.0), along(0.3), smallCov()));         // 0.3 m/s
  EXPECT_FALSE(slam.process(frame(3, 12.0), along(1.1), smallCov()));        // 0.8 m/s
  EXPECT_EQ(slam.summary().skippedSpeed, 1);
  // Slower again: updated at once, 0.2 s after the skipped frame (the rate counts from the last
  // update, 1.2 s before).
  EXPECT_TRUE(slam.process(frame(4, 12.2), along(1.15), smallCov()));        // 0.25 m/s
  EXPECT_FALSE(slam.process(frame(5, 13.2), along(1.3, 0.5), smallCov()));   // turning at 0.5 rad/s
  EXPECT_EQ(slam.summary().skippedSpeed, 2);
  EXPECT_TRUE(slam.process(frame(6, 14.2), along(1.5, 0.6), smallCov()));    // 0.1 rad/s
  EXPECT_EQ(slam.summary().nodesAdded, 4);
  EXPECT_EQ(slam.summary().skippedRate, 0);

  // No limit by default.
  Rtabmap free;
  free.init({{"Rtabmap/DetectionRate", "1"}}, "");
  ASSERT_TRUE(free.process(frame(1, 10.0), along(0.0), smallCov()));
  EXPECT_TRUE(free.process(frame(2, 11.0), along(5.0), smallCov()));
  EXPECT_EQ(free.summary().skippedSpeed, 0);
}

TEST(Rtabmap, StillRobotAndRateAddNoNode) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "1"}}, "");
  ASSERT_TRUE(slam.process(frame(1, 10.0), along(0.0), smallCov()));
  // 0.1 s later: under the 1 Hz detection rate.
  EXPECT_FALSE(slam.process(frame(2, 10.1), along(1.0), smallCov()));
  EXPECT_EQ(slam.summary().skippedRate, 1);
  // 1 s later but 1 cm away: the robot did not move (RGBD/LinearUpdate 0.1 m).
  EXPECT_FALSE(slam.process(frame(3, 11.0), along(0.01), smallCov()));
  EXPECT_EQ(slam.summary().skippedStill, 1);
  // Turning in place counts as moving (RGBD/AngularUpdate 0.1 rad).
  EXPECT_TRUE(slam.process(frame(4, 12.0), along(0.01, 0.5), smallCov()));
  EXPECT_EQ(slam.summary().nodesAdded, 2);
  EXPECT_EQ(slam.statistics().refImageId, slam.lastNodeId());
}

// Issue 10 (the soak's memory goal): what an update frees (retrieved nodes, grids read back,
// nodes transferred to the LTM) goes back to the system when the update ends, so the resident
// size follows the live data. A frame the update skips costs no release (camera rates).
TEST(Rtabmap, EachUpdateGivesTheHeapItFreedBack) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the heap release is glibc's malloc_trim";
#endif
  if (test::kMallocReplacedBySanitizer) GTEST_SKIP() << "a sanitizer replaces glibc's malloc in this build";
  if (memory::residentMemory().total == 0) GTEST_SKIP() << "no /proc/self/status here";
  constexpr size_t kMb = 1024 * 1024;
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "1"}}, "");
  ASSERT_TRUE(slam.process(frame(1, 10.0), along(0.0), smallCov()));
  EXPECT_TRUE(slam.statistics().data().count(Statistics::kTimingMemory_release));
  test::HeapHole hole(64 * kMb);
  const size_t held = memory::residentMemory().anon;
  EXPECT_FALSE(slam.process(frame(2, 10.1), along(1.0), smallCov()));  // under the detection rate
  EXPECT_GE(memory::residentMemory().anon + 8 * kMb, held) << "a skipped frame released the heap";
  ASSERT_TRUE(slam.process(frame(3, 11.0), along(1.0), smallCov()));
  const size_t after = memory::residentMemory().anon;
  EXPECT_LE(after + 48 * kMb, held) << "held " << held / kMb << " MB, after the update " << after / kMb;
}

TEST(Rtabmap, StampsGoingBackwardsAreRefusedUnlessOdometryRestarts) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  ASSERT_TRUE(slam.process(frame(1, 10.0), along(0.0), smallCov()));
  ASSERT_TRUE(slam.process(frame(2, 11.0), along(1.0), smallCov()));
  EXPECT_FALSE(slam.process(frame(3, 5.0), along(2.0), smallCov()));
  EXPECT_NE(slam.lastRejection().find("older"), std::string::npos) << slam.lastRejection();
  const int firstMap = slam.mapId();
  // A bag restarted with its odometry: identity pose and old stamps, a new map.
  EXPECT_TRUE(slam.process(frame(4, 5.0), Transform::Identity(), smallCov()));
  EXPECT_GT(slam.mapId(), firstMap);
  EXPECT_EQ(slam.summary().mapsStarted, 2);
}

// The ROS layer saw ROS time jump back (a bag played again): older stamps are accepted again and
// a new map starts even when the first frame after the restart is not at the odometry origin.
TEST(Rtabmap, ClockJumpingBackAcceptsOlderStampsInANewMap) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  ASSERT_TRUE(slam.process(frame(1, 10.0), along(0.0), smallCov()));
  ASSERT_TRUE(slam.process(frame(2, 11.0), along(1.0), smallCov()));
  const int firstMap = slam.mapId();
  ASSERT_FALSE(slam.process(frame(3, 0.5), along(0.1), smallCov()));
  slam.clockJumpedBack();
  EXPECT_TRUE(slam.process(frame(3, 0.5), along(0.1), smallCov())) << slam.lastRejection();
  EXPECT_EQ(slam.mapId(), firstMap + 1);
  EXPECT_EQ(slam.optimizedPoses().size(), 1u);
  // The new timeline is ordered again.
  EXPECT_TRUE(slam.process(frame(4, 1.5), along(0.6), smallCov()));
  EXPECT_FALSE(slam.process(frame(5, 1.0), along(0.7), smallCov()));
  EXPECT_EQ(slam.mapId(), firstMap + 1);
}

// Mem/GenerateIds false: a node takes its frame's id, which must be positive and increasing.
TEST(Rtabmap, NodesTakeTheFrameIdsWhenIdsAreNotGenerated) {
  for (const bool generate : {true, false}) {
    SCOPED_TRACE(generate ? "default" : "Mem/GenerateIds false");
    Rtabmap slam;
    ParametersMap p = everyFrame();
    p["Mem/GenerateIds"] = generate ? "true" : "false";
    slam.init(p, "");
    ASSERT_TRUE(slam.process(frame(10, 1.0), along(0.0), smallCov())) << slam.lastRejection();
    ASSERT_TRUE(slam.process(frame(20, 2.0), along(0.5), smallCov())) << slam.lastRejection();
    EXPECT_EQ(slam.lastNodeId(), generate ? 2 : 20);
    const bool older = slam.process(frame(15, 3.0), along(1.0), smallCov());
    const bool none = slam.process(frame(0, 4.0), along(1.5), smallCov());
    EXPECT_EQ(older, generate);
    EXPECT_EQ(none, generate);
    if (!generate) {
      EXPECT_NE(slam.lastRejection().find("no id"), std::string::npos) << slam.lastRejection();
    }
    const std::map<int, Transform> poses = slam.optimizedPoses();
    EXPECT_EQ(poses.begin()->first, generate ? 1 : 10);
    EXPECT_EQ(poses.size(), generate ? 4u : 2u);
  }
}

TEST(Rtabmap, OdometryResetStartsANewMapNotLinkedToTheOldOne) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * (i + 1)), smallCov()));
  const int firstMap = slam.mapId();
  ASSERT_TRUE(slam.process(frame(4, 4.0), Transform::Identity(), smallCov()));
  ASSERT_TRUE(slam.process(frame(5, 5.0), along(0.5), smallCov()));
  EXPECT_EQ(slam.mapId(), firstMap + 1);
  // The current referential holds only the new map's nodes; no link joins the two maps.
  EXPECT_EQ(slam.optimizedPoses().size(), 2u);
  for (const auto& [from, link] : slam.localLinks()) {
    EXPECT_FALSE(link.from() <= 3 && link.to() >= 4) << link.from() << "->" << link.to();
  }
  slam.triggerNewMap();
  ASSERT_TRUE(slam.process(frame(6, 6.0), along(1.0), smallCov()));
  EXPECT_EQ(slam.mapId(), firstMap + 2);
  EXPECT_EQ(slam.optimizedPoses().size(), 1u);
}

TEST(Rtabmap, UnknownParameterNamesTheClosestKey) {
  Rtabmap slam;
  try {
    slam.init({{"RGBD/LinearUpdat", "0.2"}}, "");
    FAIL() << "an unknown key was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("RGBD/LinearUpdate"), std::string::npos) << e.what();
  }
  EXPECT_THROW(slam.init({{"RGBD/LocalRadius", "-1"}}, ""), ParameterError);
}

TEST(Rtabmap, ForeignDatabaseIsRefusedAndLeftUntouched) {
  test::TempDir dir("rtabmap_slam_foreign");
  const std::string path = dir.file("notes.db");
  {
    std::ofstream out(path);
    out << "not a database, the notes of another program\n";
  }
  const auto size = std::filesystem::file_size(path);
  Rtabmap slam;
  EXPECT_THROW(slam.init(everyFrame(), path), DatabaseError);
  EXPECT_EQ(std::filesystem::file_size(path), size);
  // Localization needs a map that exists.
  EXPECT_THROW(slam.init({{"Mem/IncrementalMemory", "false"}}, dir.file("missing.db")), DatabaseError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("missing.db")));
}

TEST(Rtabmap, SessionsLabelsAndWorkingMemorySurviveARestart) {
  test::TempDir dir("rtabmap_slam_restart");
  const std::string path = dir.file("rtabmap.db");
  int firstMap = 0;
  {
    Rtabmap slam;
    slam.init(everyFrame(), path);
    for (int i = 0; i < 4; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
    firstMap = slam.mapId();
    EXPECT_TRUE(slam.setLabel(2, "kitchen"));
    EXPECT_FALSE(slam.setLabel(3, "kitchen")) << "a label names one node";
    EXPECT_FALSE(slam.setLabel(999, "nowhere")) << "unknown node";
    slam.close();
  }
  Rtabmap slam;
  slam.init(everyFrame(), path);
  EXPECT_GT(slam.mapId(), firstMap);
  EXPECT_EQ(slam.nodeOfLabel("kitchen"), 2);
  EXPECT_EQ(slam.nodeOfLabel("map" + std::to_string(firstMap)), 1) << "first node of a map is labelled";
  // The previous session's nodes are back in Working Memory, candidates for loop closure.
  const std::vector<int> wm = slam.workingMemory();
  EXPECT_EQ(wm.size(), 4u);
  // A new session does not link itself to the old map: its first node is in a new referential.
  ASSERT_TRUE(slam.process(frame(10, 10.0), along(0.0), smallCov()));
  EXPECT_EQ(slam.optimizedPoses().size(), 1u);
  EXPECT_GT(slam.lastNodeId(), 4);
}

TEST(Rtabmap, NextSessionStartsWithTheWorkingMemoryTheLastOneClosedWith) {
  test::TempDir dir("rtabmap_slam_wm");
  const std::string path = dir.file("rtabmap.db");
  std::vector<int> closedWith;
  {
    Rtabmap slam;
    slam.init({{"Rtabmap/DetectionRate", "0"}, {"Rtabmap/MemoryThr", "3"}, {"Mem/STMSize", "2"}}, path);
    for (int i = 0; i < 12; ++i) ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
    // The last frame: the robot did not move; nothing is added.
    EXPECT_FALSE(slam.process(frame(13, 13.0), along(5.52), smallCov()));
    closedWith = slam.workingMemory();
    ASSERT_LT(closedWith.size(), 12u) << "memory management kept WM small";
    slam.close();
  }
  Rtabmap slam;
  slam.init(everyFrame(), path);
  std::vector<int> wm = slam.workingMemory();
  std::sort(wm.begin(), wm.end());
  std::sort(closedWith.begin(), closedWith.end());
  EXPECT_EQ(wm, closedWith);
  Rtabmap all;
  slam.close();
  all.init({{"Rtabmap/DetectionRate", "0"}, {"Mem/InitWMWithAllNodes", "true"}}, path);
  EXPECT_EQ(all.workingMemory().size(), 12u);
}

// The statistics say which node is safe on disk: once a node has left STM its write commits in
// the background; Memory/Durable_node_id reaches it, never a node still in STM, and the node it
// names is in the database (read by another connection while the map is open).
TEST(Rtabmap, StatisticsTellTheLastNodeSafeOnDisk) {
  test::TempDir dir("rtabmap_slam_durable");
  const std::string path = dir.file("rtabmap.db");
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"}, {"Mem/STMSize", "3"}}, path);
  float durable = 0.0f;
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(slam.process(frame(i + 1, i + 1.0), along(0.5 * i), smallCov()));
    const auto& data = slam.statistics().data();
    ASSERT_TRUE(data.count("Memory/Durable_node_id/"));
    EXPECT_EQ(data.at("Memory/Database_write_failed/"), 0.0f);
    durable = data.at("Memory/Durable_node_id/");
    EXPECT_LE(durable, static_cast<float>(std::max(0, slam.lastNodeId() - 3))) << "a node still in STM cannot be on disk";
  }
  // The writer commits in the background: give it a moment, then the next update tells.
  for (int i = 0; i < 50 && durable < 7.0f; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_TRUE(slam.process(frame(11 + i, 11.0 + i), along(5.0 + 0.5 * i), smallCov()));
    durable = slam.statistics().data().at("Memory/Durable_node_id/");
  }
  ASSERT_GE(durable, 7.0f);
  db::Database::Options readOnly;
  readOnly.readOnly = true;
  db::Database reader(path, readOnly);
  EXPECT_TRUE(reader.loadNode(static_cast<int>(durable), db::LoadOptions::nodeOnly()).has_value());
  slam.close();
}

TEST(Rtabmap, GoalsByIdLabelAndPoseAreFollowedUntilReached) {
  Rtabmap slam;
  slam.init(everyFrame(), "");
  // A 5 m corridor, one node every 0.5 m, then back to the start.
  int stamp = 0;
  auto next = [&stamp] {
    ++stamp;
    return frame(stamp, stamp);
  };
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(slam.process(next(), along(0.5 * i), smallCov()));
  ASSERT_TRUE(slam.setLabel(6, "printer"));
  EXPECT_FALSE(slam.setGoal(999));
  EXPECT_NE(slam.lastRejection().find("no path"), std::string::npos) << slam.lastRejection();
  EXPECT_FALSE(slam.setGoal(std::string("kitchen")));
  EXPECT_NE(slam.lastRejection().find("kitchen"), std::string::npos);

  ASSERT_TRUE(slam.setGoal(std::string("printer"))) << slam.lastRejection();
  const auto path = slam.goalPath();
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.front().first, slam.lastNodeId());
  EXPECT_EQ(path.back().first, 6);
  // The robot drives back: the current goal is the farthest path node within RGBD/LocalRadius.
  ASSERT_TRUE(slam.process(next(), Transform(4.5, 0, 0, 0, 0, M_PI), smallCov()));
  EXPECT_EQ(slam.statistics().currentGoalId, 6);
  EXPECT_FALSE(slam.goalReached());
  bool reached = false;
  for (double x = 4.0; x >= 2.4 && !reached; x -= 0.5) {
    ASSERT_TRUE(slam.process(next(), Transform(x, 0, 0, 0, 0, M_PI), smallCov()));
    reached = slam.goalReached();
  }
  EXPECT_TRUE(reached) << "node 6 is at 2.5 m, RGBD/GoalReachedRadius 0.5 m";
  EXPECT_TRUE(slam.goalPath().empty()) << "a reached goal ends the plan";

  // A pose goal goes to the node nearest to it.
  ASSERT_TRUE(slam.setGoal(Transform(0.6, 0.1, 0, 0, 0, 0)));
  EXPECT_EQ(slam.goalPath().back().first, 2);
  slam.cancelGoal();
  EXPECT_TRUE(slam.goalPath().empty());
}

// RGBD/GoalsSavedInUserData: the node where the robot was given a goal keeps "GOAL:<label>"
// (or the goal node's id), in the database too; user data already there stays, and nothing is
// written by default.
TEST(Rtabmap, AcceptedGoalsAreWrittenInTheUserDataOfTheRobotsNode) {
  test::TempDir dir("rtabmap_slam_goals");
  auto text = [](const SensorData& data) {
    const cv::Mat raw = data.userDataRaw().empty() ? codec::uncompressData(data.userDataCompressed()) : data.userDataRaw();
    return raw.empty() ? std::string() : std::string(raw.ptr<char>(0), raw.total());
  };
  for (const bool saved : {false, true}) {
    SCOPED_TRACE(saved ? "RGBD/GoalsSavedInUserData" : "default");
    const std::string path = dir.file(saved ? "goals.db" : "default.db");
    Rtabmap slam;
    ParametersMap p = everyFrame();
    p["RGBD/GoalsSavedInUserData"] = saved ? "true" : "false";
    slam.init(p, path);
    int stamp = 0;
    for (int i = 0; i <= 10; ++i, ++stamp) ASSERT_TRUE(slam.process(frame(stamp + 1, stamp + 1.0), along(0.5 * i), smallCov()));
    ASSERT_TRUE(slam.setLabel(6, "printer"));
    const int first = slam.lastNodeId();
    ASSERT_TRUE(slam.setGoal(std::string("printer"))) << slam.lastRejection();
    ASSERT_TRUE(slam.setGoal(3)) << slam.lastRejection();  // same node: the first goal stays
    ASSERT_TRUE(slam.process(frame(stamp + 1, stamp + 1.0), Transform(4.5, 0, 0, 0, 0, M_PI), smallCov()));
    const int second = slam.lastNodeId();
    ASSERT_NE(second, first);
    ASSERT_TRUE(slam.setGoal(2)) << slam.lastRejection();
    EXPECT_EQ(text(slam.node(first)->sensorData()), saved ? "GOAL:printer" : "");
    EXPECT_EQ(text(slam.node(second)->sensorData()), saved ? "GOAL:2" : "");
    slam.close();
    db::Database::Options readOnly;
    readOnly.readOnly = true;
    db::Database reader(path, readOnly);
    EXPECT_EQ(text(reader.loadNode(first)->sensorData()), saved ? "GOAL:printer" : "");
    EXPECT_EQ(text(reader.loadNode(second)->sensorData()), saved ? "GOAL:2" : "");
    EXPECT_EQ(text(reader.loadNode(first - 1)->sensorData()), "");
  }
}

}  // namespace
}  // namespace rtabmap
