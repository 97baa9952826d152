// Mem/ReduceGraph in the SLAM pipeline: a node that closed a loop with an older one merges into
// it as it leaves STM, so driving a route again does not grow the graph, and the nodes kept stay
// where they are (as close to the truth as with the full graph).
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "PoseOnlyFrames.h"
#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/slam/Rtabmap.h"

namespace rtabmap {
namespace {

using test::smallCov;

struct RouteRun {
  SlamSummary summary;
  std::map<int, Transform> poses;
  std::map<int, int> reducedIds;  // gathered from every update's statistics
};

// Out 3 m along x (nodes 1-11, 0.3 m apart) and back along the same line (nodes 12-21), the
// odometry 3% long on the way back. Each node on the way back is linked by the user (standing
// in for loop-closure detection) to its twin on the way out: the same position, facing back.
RouteRun outAndBack(bool reduce, const std::string& database) {
  Rtabmap slam;
  slam.init({{"Rtabmap/DetectionRate", "0"}, {"Mem/STMSize", "3"}, {"Mem/ReduceGraph", reduce ? "true" : "false"}},
            database);
  RouteRun run;
  for (int i = 0; i <= 20; ++i) {
    const bool back = i > 10;
    const double odomX = back ? 3.0 - 1.03 * 0.3 * (i - 10) : 0.3 * i;
    EXPECT_TRUE(slam.process(test::frame(i + 1, 10.0 + i), Transform(odomX, 0, 0, 0, 0, back ? M_PI : 0.0), smallCov()))
        << slam.lastRejection();
    for (const auto& [id, into] : slam.statistics().reducedIds) run.reducedIds[id] = into;
    if (back) {
      const int twin = 21 - i;  // node of index 20 - i on the way out
      const Link closure(slam.lastNodeId(), twin, Link::kUserClosure, Transform(0, 0, 0, 0, 0, M_PI),
                         Link::InfMatrix::Identity() * 1e4);
      EXPECT_TRUE(slam.addLink(closure)) << slam.lastRejection();
    }
  }
  run.summary = slam.summary();
  run.poses = slam.optimizedPoses();
  slam.close();
  return run;
}

TEST(ReduceGraph, ARouteDrivenAgainKeepsTheNodesOfTheFirstPass) {
  rtabmap::test::TempDir dir;
  const RouteRun full = outAndBack(false, dir.file("full.db"));
  const RouteRun reduced = outAndBack(true, dir.file("reduced.db"));
  EXPECT_EQ(full.summary.reducedNodes, 0);
  ASSERT_EQ(full.poses.size(), 21u);
  // Nodes 12-18 left STM (Mem/STMSize 3) after their loop closure: each merged into its twin.
  EXPECT_EQ(reduced.summary.reducedNodes, 7);
  std::map<int, int> expected;
  for (int id = 12; id <= 18; ++id) expected[id] = 22 - id;
  EXPECT_EQ(reduced.reducedIds, expected);
  ASSERT_EQ(reduced.poses.size(), 14u);
  for (int id = 12; id <= 18; ++id) EXPECT_EQ(reduced.poses.count(id), 0u) << id;
  // The composed links keep the map together: every node it kept is where it was (the way out
  // measured exactly, the way back 3% long), within 2 cm, as close as the full graph has it
  // (which trusts the long way back more: 4.3 cm off at the far end; here 0.9 cm).
  const auto truth = [](int id) { return id <= 11 ? 0.3 * (id - 1) : 0.3 * (21 - id); };
  for (const auto& [id, pose] : reduced.poses) {
    const double error = std::fabs(pose.x() - truth(id));
    EXPECT_LT(error, 0.02) << "node " << id << " " << pose.prettyPrint();
    EXPECT_LT(error, std::fabs(full.poses.at(id).x() - truth(id)) + 0.005) << "node " << id;
  }
  // The robot is back at the start in both, not where odometry put it (9 cm off).
  EXPECT_LT(reduced.poses.rbegin()->second.getNorm(), 0.03);
  EXPECT_LT(full.poses.rbegin()->second.getNorm(), 0.03);

  // The database has only what the reduced map holds, every link between nodes it has.
  db::DatabaseOptions readOnly;
  readOnly.readOnly = true;
  db::Database database(dir.file("reduced.db"), readOnly);
  const std::vector<int> ids = database.nodeIds();
  EXPECT_EQ(ids.size(), 14u);
  const std::set<int> saved(ids.begin(), ids.end());
  for (const auto& [from, link] : database.loadAllLinks(true)) {
    EXPECT_TRUE(saved.count(from) && saved.count(link.to())) << from << "->" << link.to();
  }
  EXPECT_EQ(database.neighborIds(1, 30).size(), ids.size());  // one connected graph
}

}  // namespace
}  // namespace rtabmap
