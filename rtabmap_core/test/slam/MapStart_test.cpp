// When a map may start: Rtabmap/StartNewMapOnGoodSignature (not on a frame without enough
// visual words) and Rtabmap/StartNewMapOnLoopClosure (not before a loop closure with an earlier
// map: every session joins the earlier ones).
#include <gtest/gtest.h>

#include <algorithm>

#include "PoseOnlyFrames.h"
#include "SimSlam.h"
#include "TexturedFrames.h"
#include "common/TestData.h"

namespace rtabmap {
namespace {

using test::along;
using test::smallCov;
using test::texturedFrame;

TEST(MapStart, AMapStartsOnlyOnANodeWithEnoughWords) {
  for (const bool wait : {false, true}) {
    SCOPED_TRACE(wait ? "StartNewMapOnGoodSignature" : "default");
    Rtabmap slam;
    ParametersMap p = test::everyFrame();
    p["Rtabmap/StartNewMapOnGoodSignature"] = wait ? "true" : "false";
    slam.init(p, "");
    // A camera still covered (no texture, no word), then the scene.
    const bool blank = slam.process(texturedFrame(1, 1.0, false), along(0.0), smallCov());
    EXPECT_EQ(blank, !wait) << slam.lastRejection();
    if (wait) {
      EXPECT_NE(slam.lastRejection().find("too few visual words"), std::string::npos) << slam.lastRejection();
      EXPECT_EQ(slam.summary().skippedMapStart, 1);
      EXPECT_EQ(slam.lastNodeId(), 0);
    }
    ASSERT_TRUE(slam.process(texturedFrame(2, 2.0), along(0.5), smallCov())) << slam.lastRejection();
    EXPECT_EQ(slam.summary().nodesAdded, wait ? 1 : 2);
    const std::optional<Signature> first = slam.node(slam.optimizedPoses().begin()->first);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->isBadSignature(), !wait) << "the map's first node";
    // Once the map has started, a blank frame is a node like any other.
    EXPECT_TRUE(slam.process(texturedFrame(3, 3.0, false), along(1.0), smallCov()));
  }
}

// The simulator's second session starts away from where the first one went: by default its
// first nodes make a map of their own until a loop closure merges it; with the option they are
// discarded, and the first node kept is one linked to the first session.
TEST(MapStart, ASessionKeepsNodesOnlyFromItsFirstLoopClosureWithAnEarlierMap) {
  REQUIRE_SIM(folder, "multisession");
  ParametersMap p = test::simSlamParameters();
  p["Rtabmap/StartNewMapOnLoopClosure"] = "true";
  test::TempDir dir("rtabmap_slam_map_start");
  const std::string db = dir.file("rtabmap.db");
  test::SimSlamRun first, second;
  test::runSimSlam(folder + "/session1", p, db, first);
  EXPECT_EQ(first.summary.skippedMapStart, 0) << "no earlier map: the first session maps from its first frame";
  ASSERT_GT(first.summary.nodesAdded, 50);
  test::runSimSlam(folder + "/session2", p, db, second);
  RecordProperty("frames_discarded", second.summary.skippedMapStart);
  EXPECT_GT(second.summary.skippedMapStart, 0);
  ASSERT_GT(second.summary.nodesAdded, 20);

  // Session 2's first node kept: linked to session 1 by a loop closure.
  int firstOfSecond = 0;
  for (const auto& [id, pose] : second.odometry) {
    (void)pose;
    if (!first.odometry.count(id) && (firstOfSecond == 0 || id < firstOfSecond)) firstOfSecond = id;
  }
  ASSERT_NE(firstOfSecond, 0);
  const bool linked = std::any_of(second.links.begin(), second.links.end(), [&](const auto& l) {
    const Link& k = l.second;
    const int other = k.from() == firstOfSecond ? k.to() : k.to() == firstOfSecond ? k.from() : 0;
    return other != 0 && first.odometry.count(other) && k.type() != Link::kNeighbor;
  });
  EXPECT_TRUE(linked) << "node " << firstOfSecond << " has no loop closure with the first session";
  // And every node of both sessions is in the one referential at the end.
  for (const auto& [id, pose] : first.odometry) {
    (void)pose;
    EXPECT_TRUE(second.optimized.count(id)) << "node " << id << " of session 1 not in the final referential";
  }
}

}  // namespace
}  // namespace rtabmap
