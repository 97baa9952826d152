// PathPlanner on a synthetic map (metres):
//
//        21 -- 22 -- 23 -- 24 -- 25 -- 26 -- 27        detour branch, y = 3
//        |                                   |
//   1 -- 2 -- 3 -- 4 -- 5 -- 6 -- 7 -- 8 -- 9 -- 10 -- 11     corridor, y = 0, x = id - 1
//
// node 21 is above node 3 (x = 2) and node 27 above node 9 (x = 8): from 3 to 9 the corridor is
// 6 m, the detour 12 m; the corridor and the detour form a loop. Nodes 101..103 (y = 20) form
// another component (a session no loop closure links to). Landmark -1 is seen from 1 and 11.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/slam/PathPlanner.h"

namespace rtabmap {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct TestMap {
  graph::Poses poses;
  graph::Links links;

  void add(int id, double x, double y, double yaw = 0.0) { poses[id] = Transform(x, y, yaw); }
  void link(int a, int b, Link::Type type = Link::kNeighbor) {
    links.emplace(a, Link(a, b, type, poses.at(a).inverse() * poses.at(b)));
  }
  void unlink(int a, int b) {
    for (auto it = links.begin(); it != links.end();) {
      const bool match = (it->second.from() == a && it->second.to() == b) ||
                         (it->second.from() == b && it->second.to() == a);
      it = match ? links.erase(it) : std::next(it);
    }
  }
};

TestMap corridorLoop() {
  TestMap m;
  for (int id = 1; id <= 11; ++id) m.add(id, id - 1, 0.0);
  for (int id = 21; id <= 27; ++id) m.add(id, id - 19, 3.0);
  for (int id = 101; id <= 103; ++id) m.add(id, id - 101, 20.0);
  m.poses[-1] = Transform(5.0, -1.0, 0.0);
  for (int id = 1; id < 11; ++id) m.link(id, id + 1);
  m.link(3, 21, Link::kGlobalClosure);
  for (int id = 21; id < 27; ++id) m.link(id, id + 1);
  m.link(27, 9, Link::kLocalSpaceClosure);
  m.link(101, 102);
  m.link(102, 103);
  m.links.emplace(1, Link(1, -1, Link::kLandmark, Transform(5.0, -1.0, 0.0)));
  m.links.emplace(11, Link(11, -1, Link::kLandmark, Transform(-5.0, -1.0, 0.0)));
  return m;
}

std::vector<int> idsOf(const std::vector<std::pair<int, Transform>>& path) {
  std::vector<int> ids;
  for (const auto& node : path) ids.push_back(node.first);
  return ids;
}

std::vector<int> range(int first, int last) {
  std::vector<int> ids;
  for (int id = first; id <= last; ++id) ids.push_back(id);
  return ids;
}

graph::Poses only(const graph::Poses& poses, const std::vector<int>& ids) {
  graph::Poses out;
  for (int id : ids) out[id] = poses.at(id);
  return out;
}

PlannerOptions options(float localRadius = 10.0f, int maxRetrieved = 2, int stuck = 0) {
  PlannerOptions o;
  o.localRadius = localRadius;
  o.maxRetrieved = maxRetrieved;
  o.stuckIterations = stuck;
  o.goalReachedRadius = 0.2f;
  return o;
}

// ---- Options ------------------------------------------------------------------------------------

TEST(PlannerOptions, ReadsTheRGBDParametersAndRejectsBadValues) {
  const PlannerOptions o = PlannerOptions::fromParameters({{"RGBD/GoalReachedRadius", "0.3"},
                                                           {"RGBD/PlanStuckIterations", "7"},
                                                           {"RGBD/PlanAngularVelocity", "0.5"},
                                                           {"RGBD/MaxLocalRetrieved", "4"},
                                                           {"RGBD/LocalRadius", "2.5"},
                                                           {"Reg/Force3DoF", "true"}});
  EXPECT_FLOAT_EQ(0.3f, o.goalReachedRadius);
  EXPECT_EQ(7, o.stuckIterations);
  EXPECT_FLOAT_EQ(0.5f, o.angularVelocity);
  EXPECT_FLOAT_EQ(0.0f, o.linearVelocity);
  EXPECT_EQ(4, o.maxRetrieved);
  EXPECT_FLOAT_EQ(2.5f, o.localRadius);
  EXPECT_TRUE(o.is2D);

  PlannerOptions bad = options();
  bad.localRadius = 0.0f;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(std::string::npos, why.find("RGBD/LocalRadius")) << why;
  EXPECT_THROW(PathPlanner{bad}, std::invalid_argument);
  EXPECT_THROW(PlannerOptions::fromParameters({{"RGBD/LocalRadius", "-1"}}), ParameterError);
}

// ---- Planning -----------------------------------------------------------------------------------

TEST(PathPlanner, FindsTheCheapestPathAroundTheLoop) {
  TestMap m = corridorLoop();
  PathPlanner planner(options());
  PlanResult r = planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ(range(1, 11), idsOf(r.path));
  EXPECT_NEAR(10.0, r.cost, 1e-9);
  EXPECT_EQ(11, planner.goalId());
  EXPECT_TRUE(planner.isActive());

  // The corridor blocked between 5 and 6: the only way is the 12 m detour.
  m.unlink(5, 6);
  r = planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ((std::vector<int>{1, 2, 3, 21, 22, 23, 24, 25, 26, 27, 9, 10, 11}), idsOf(r.path));
  EXPECT_NEAR(16.0, r.cost, 1e-9);
}

TEST(PathPlanner, DoesNotGoThroughALandmark) {
  TestMap m = corridorLoop();
  m.unlink(5, 6);
  m.unlink(3, 21);  // 1 and 11 are now connected only through landmark -1
  PathPlanner planner(options());
  const PlanResult r = planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1));
  EXPECT_FALSE(r.found);
  EXPECT_NE(std::string::npos, r.why.find("not connected")) << r.why;
}

TEST(PathPlanner, AngularCostPrefersTheLongerPathWithoutTurns) {
  TestMap m = corridorLoop();
  for (int id = 4; id <= 8; ++id) m.poses[id] = Transform(id - 1, 0.0, id % 2 ? kPi / 2 : -kPi / 2);
  PlannerOptions o = options();
  PathPlanner byDistance(o);
  PlanResult r = byDistance.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ(range(1, 11), idsOf(r.path));

  o.linearVelocity = 1.0f;
  o.angularVelocity = 0.5f;  // the corridor turns 5 pi rad: 31 s, more than the 6 s detour
  PathPlanner byTime(o);
  r = byTime.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ((std::vector<int>{1, 2, 3, 21, 22, 23, 24, 25, 26, 27, 9, 10, 11}), idsOf(r.path));
  EXPECT_NEAR(16.0, r.cost, 1e-9);  // no turn on the detour: 16 m at 1 m/s
}

TEST(PathPlanner, PoseGoalGoesToTheNearestNodeAndEndsAtThePose) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  const Transform target(7.2, 0.3, 0.0);
  const PlanResult r = planner.plan(PlanGoal::at(target), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ(8, r.goalNodeId);
  EXPECT_EQ(range(1, 8), idsOf(r.path));
  EXPECT_NEAR(0.0, graph::poseDistance(target, planner.goalPose()), 1e-9);

  // At node 8 (0.36 m from the pose) the goal is not reached; at the pose it is.
  PlanStatus s = planner.update(m.poses, m.poses.at(8));
  EXPECT_FALSE(s.goalReached);
  EXPECT_EQ(8, s.currentGoalId);
  EXPECT_NEAR(0.0, graph::poseDistance(target, s.currentGoalPose), 1e-9);
  s = planner.update(m.poses, Transform(7.15, 0.3, 0.0));
  EXPECT_TRUE(s.goalReached);
  EXPECT_FALSE(planner.isActive());
}

TEST(PathPlanner, PoseGoalFollowsItsNodeWhenTheGraphMoves) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  ASSERT_TRUE(planner.plan(PlanGoal::at(Transform(7.2, 0.3, 0.0)), m.poses, m.links, 1, m.poses.at(1)).found);
  graph::Poses reoptimised = m.poses;
  reoptimised[8] = Transform(7.0, 1.0, 0.0);  // node 8 moved 1 m up
  const PlanStatus s = planner.update(reoptimised, m.poses.at(5));
  EXPECT_EQ(8, s.currentGoalId);
  EXPECT_NEAR(7.2, s.currentGoalPose.x(), 1e-9);
  EXPECT_NEAR(1.3, s.currentGoalPose.y(), 1e-9);
}

TEST(PathPlanner, PoseGoalIgnoresNodesOfOtherComponents) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  // Nearest of all is 102 (another referential); nearest reachable is 21 at (2, 3).
  const PlanResult r = planner.plan(PlanGoal::at(Transform(1.0, 19.0, 0.0)), m.poses, m.links, 1, m.poses.at(1));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ(21, r.goalNodeId);
}

TEST(PathPlanner, ReportsUnknownAndUnreachableGoalsInWords) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  PlanResult r = planner.plan(PlanGoal::node(999), m.poses, m.links, 1, m.poses.at(1));
  EXPECT_FALSE(r.found);
  EXPECT_NE(std::string::npos, r.why.find("999")) << r.why;
  EXPECT_NE(std::string::npos, r.why.find("unknown")) << r.why;
  EXPECT_FALSE(planner.isActive());

  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  r = planner.plan(PlanGoal::node(102), m.poses, m.links, 1, m.poses.at(1));
  EXPECT_FALSE(r.found);
  EXPECT_NE(std::string::npos, r.why.find("102")) << r.why;
  EXPECT_NE(std::string::npos, r.why.find("not connected")) << r.why;
  EXPECT_FALSE(planner.isActive()) << "a failed plan replaces the previous one";

  r = planner.plan(PlanGoal::node(11), m.poses, m.links, 55, Transform());
  EXPECT_FALSE(r.found);
  EXPECT_NE(std::string::npos, r.why.find("cannot locate the robot")) << r.why;
  r = planner.plan(PlanGoal(), m.poses, m.links, 1, m.poses.at(1));
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.why.empty());
}

TEST(PathPlanner, StartsFromTheNodeNearestTheRobotWhenTheCurrentNodeIsUnknown) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  const PlanResult r = planner.plan(PlanGoal::node(11), m.poses, m.links, 0, Transform(6.1, 0.2, 0.0));
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_EQ(range(7, 11), idsOf(r.path));
}

// ---- Following ----------------------------------------------------------------------------------

TEST(PathPlanner, CurrentGoalAdvancesWithinTheLocalRadius) {
  const TestMap m = corridorLoop();
  const float radius = 3.5f;
  PathPlanner planner(options(radius));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);

  int previousGoal = 0;
  for (double x = 0.05; x < 9.75; x += 0.3) {  // never half-way: no tie for the nearest node
    const Transform robot(x, 0.05, 0.0);
    const PlanStatus s = planner.update(m.poses, robot);
    SCOPED_TRACE("robot at x = " + std::to_string(x));
    ASSERT_FALSE(s.failed) << s.why;
    ASSERT_FALSE(s.goalReached);
    ASSERT_NE(0, s.currentGoalId);
    EXPECT_LE(graph::poseDistance(robot, s.currentGoalPose), radius);
    EXPECT_GE(s.currentGoalId, previousGoal) << "the goal never moves back along the path";
    // The farthest node within the radius (path length from the nearest node, robot offset).
    const int nearest = static_cast<int>(std::lround(x)) + 1;
    const double offset = std::hypot(x - (nearest - 1), 0.05);
    const int expected = std::min(11, nearest + static_cast<int>(std::floor(radius - offset)));
    EXPECT_EQ(expected, s.currentGoalId);
    EXPECT_EQ(nearest, s.progressNodeId);
    previousGoal = s.currentGoalId;
  }
  EXPECT_TRUE(planner.update(m.poses, Transform(9.9, 0.0, 0.0)).goalReached);
}

TEST(PathPlanner, ProgressNeverGoesBackAlongThePath) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options(3.5f));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  EXPECT_EQ(7, planner.update(m.poses, m.poses.at(4)).currentGoalId);
  const PlanStatus s = planner.update(m.poses, m.poses.at(1));  // pushed back to the start
  EXPECT_EQ(4, s.progressNodeId);
  EXPECT_EQ(4, s.currentGoalId) << "the progress node (3 + 1 m > 3.5 m to the next one)";
  EXPECT_EQ(0u, s.immune.count(2)) << "nodes behind are not protected any more";
}

TEST(PathPlanner, CurrentGoalStopsBeforeNodesMissingFromTheLocalMap) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options(20.0f, 2));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  const graph::Poses local = only(m.poses, {1, 2, 3, 4, 5, 7, 8});  // 6 and 9..11 in LTM
  const PlanStatus s = planner.update(local, m.poses.at(1));
  EXPECT_EQ(5, s.currentGoalId);
  EXPECT_EQ((std::vector<int>{6, 9}), s.toRetrieve) << "path order, at most RGBD/MaxLocalRetrieved";
  EXPECT_EQ((std::set<int>{1, 2, 3, 4, 5, 7, 8}), s.immune);
}

TEST(PathPlanner, RetrievesUpcomingPathNodesInOrderUpToTheLimit) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options(10.0f, 3));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  graph::Poses local = only(m.poses, {1, 2, 3});
  PlanStatus s = planner.update(local, m.poses.at(1));
  EXPECT_EQ((std::vector<int>{4, 5, 6}), s.toRetrieve);
  EXPECT_EQ(3, s.currentGoalId);

  // Retrieved; the robot moves on and node 1 was transferred behind it.
  local = only(m.poses, {2, 3, 4, 5, 6});
  s = planner.update(local, m.poses.at(3));
  EXPECT_EQ((std::vector<int>{7, 8, 9}), s.toRetrieve);
  EXPECT_EQ(6, s.currentGoalId);
  EXPECT_EQ((std::set<int>{3, 4, 5, 6}), s.immune);

  PathPlanner noRetrieval(options(10.0f, 0));
  ASSERT_TRUE(noRetrieval.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  EXPECT_TRUE(noRetrieval.update(only(m.poses, {1, 2}), m.poses.at(1)).toRetrieve.empty());
}

TEST(PathPlanner, GoalReachedWithinTheRadiusOnly) {
  const TestMap m = corridorLoop();
  PlannerOptions o = options();
  o.goalReachedRadius = 0.5f;
  PathPlanner planner(o);
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  PlanStatus s = planner.update(m.poses, Transform(9.4, 0.0, 0.0));
  EXPECT_FALSE(s.goalReached);
  EXPECT_TRUE(planner.isActive());
  s = planner.update(m.poses, Transform(9.6, 0.1, 0.0));
  EXPECT_TRUE(s.goalReached);
  EXPECT_FALSE(s.failed);
  EXPECT_EQ(11, s.currentGoalId);
  EXPECT_FALSE(planner.isActive());
  EXPECT_EQ(0, planner.goalId());
  EXPECT_EQ(0, planner.update(m.poses, Transform(9.6, 0.1, 0.0)).currentGoalId) << "inactive";
}

TEST(PathPlanner, FailsAfterStuckIterationsWithoutProgress) {
  const TestMap m = corridorLoop();
  const int stuck = 4;
  // Radius 1.5 from node 1: only node 2 ahead qualifies (node 1, the progress node, is 0.4 m
  // away, beyond the reached radius, so it is a fallback goal after node 2 is given up on).
  PathPlanner planner(options(1.5f, 2, stuck));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  const Transform blocked(0.0, 0.4, 0.0);
  PlanStatus s;
  for (int i = 0; i <= stuck; ++i) {
    s = planner.update(m.poses, blocked);
    ASSERT_FALSE(s.failed) << "update " << i << ": " << s.why;
  }
  EXPECT_EQ(1, s.currentGoalId) << "node 2 given up on after " << stuck << " updates";
  EXPECT_EQ(1u, planner.unreachableNodes().count(2));
  for (int i = 0; i < stuck - 1; ++i) ASSERT_FALSE(planner.update(m.poses, blocked).failed);
  s = planner.update(m.poses, blocked);
  EXPECT_TRUE(s.failed);
  EXPECT_NE(std::string::npos, s.why.find("no progress")) << s.why;
  EXPECT_FALSE(planner.isActive());
}

TEST(PathPlanner, ProgressResetsTheStuckCount) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options(1.5f, 2, 3));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  // Slowly but steadily closer to node 2: never stuck, even over many updates.
  for (int i = 0; i < 30; ++i) {
    const PlanStatus s = planner.update(m.poses, Transform(0.0, 0.45 - 0.01 * i, 0.0));
    ASSERT_FALSE(s.failed) << "update " << i << ": " << s.why;
    ASSERT_EQ(2, s.currentGoalId);
  }
  EXPECT_TRUE(planner.unreachableNodes().empty());

  PathPlanner never(options(1.5f, 2, 0));  // 0 = disabled
  ASSERT_TRUE(never.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  for (int i = 0; i < 50; ++i) ASSERT_FALSE(never.update(m.poses, Transform(0.0, 0.4, 0.0)).failed);
}

TEST(PathPlanner, FailsWhenThePathAheadNeverEntersTheLocalMap) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options(10.0f, 2, 3));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  // The robot's local map holds only the detour: every path node is in LTM and never comes back.
  const graph::Poses local = only(m.poses, {21, 22});
  for (int i = 0; i < 3; ++i) {
    const PlanStatus s = planner.update(local, Transform(0.0, 0.5, 0.0));
    ASSERT_FALSE(s.failed) << s.why;
    EXPECT_EQ(0, s.currentGoalId);
    EXPECT_EQ((std::vector<int>{1, 2}), s.toRetrieve);
  }
  const PlanStatus s = planner.update(local, Transform(0.0, 0.5, 0.0));
  EXPECT_TRUE(s.failed);
  EXPECT_NE(std::string::npos, s.why.find("not been in the local map")) << s.why;
}

// ---- Virtual links ------------------------------------------------------------------------------

TEST(PathPlanner, VirtualLinksBridgeGapsOfThePathInTheLocalMap) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  // Node 6 is in LTM: the local map holds 5 and 7 without a link between them.
  const graph::Poses local = only(m.poses, {1, 2, 3, 4, 5, 7, 8, 9, 10, 11});
  graph::Links localLinks;
  for (const auto& [key, link] : m.links) {
    if (local.count(link.from()) && local.count(link.to())) localLinks.emplace(key, link);
  }
  std::vector<Link> links = planner.temporaryLinks(local, localLinks);
  ASSERT_EQ(1u, links.size());
  EXPECT_EQ(5, links[0].from());
  EXPECT_EQ(7, links[0].to());
  EXPECT_EQ(Link::kVirtualClosure, links[0].type());
  EXPECT_NEAR(2.0, links[0].transform().x(), 1e-9);
  EXPECT_NEAR(0.0, links[0].transform().y(), 1e-9);
  EXPECT_TRUE(links[0].isValid());

  // A proximity link 5 -> 7 already keeps them connected: nothing to add.
  localLinks.emplace(7, Link(7, 5, Link::kLocalSpaceClosure, m.poses.at(7).inverse() * m.poses.at(5)));
  EXPECT_TRUE(planner.temporaryLinks(local, localLinks).empty());

  // Adjacent path nodes whose link the caller's local links lack get one too; nodes behind the
  // progress node do not.
  localLinks.clear();
  planner.update(local, m.poses.at(9));
  links = planner.temporaryLinks(local, localLinks);
  ASSERT_EQ(2u, links.size());
  EXPECT_EQ(9, links[0].from());
  EXPECT_EQ(10, links[0].to());
  EXPECT_EQ(10, links[1].from());
  EXPECT_EQ(11, links[1].to());
}

TEST(PathPlanner, ANodeMergedIntoAnotherIsRenamedOnThePath) {
  // Mem/ReduceGraph merged path nodes into the nodes they closed loops with: the path goes
  // through those, once where two consecutive nodes became one, and the goal follows.
  const TestMap m = corridorLoop();
  PathPlanner planner(options(20.0f, 2));
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  planner.update(m.poses, m.poses.at(3));  // progress at node 3
  const Transform goalPose = planner.goalPose();
  planner.renameNode(5, 4);  // 5 was 4 seen again
  planner.renameNode(7, 23);
  planner.renameNode(11, 10);  // the goal
  EXPECT_EQ((std::vector<int>{1, 2, 3, 4, 6, 23, 8, 9, 10}), idsOf(planner.path()));
  EXPECT_EQ(10, planner.goalId());
  EXPECT_LT(planner.goalPose().getDistance(goalPose), 1e-9) << "the goal stays where it was planned";
  const PlanStatus s = planner.update(m.poses, m.poses.at(3));
  EXPECT_FALSE(s.failed) << s.why;
  planner.renameNode(3, 2);  // where the robot is: progress stays on it
  EXPECT_EQ((std::vector<int>{1, 2, 4, 6, 23, 8, 9, 10}), idsOf(planner.path()));
  EXPECT_FALSE(planner.update(m.poses, m.poses.at(3)).failed);
}

TEST(PathPlanner, CancelEndsThePlan) {
  const TestMap m = corridorLoop();
  PathPlanner planner(options());
  ASSERT_TRUE(planner.plan(PlanGoal::node(11), m.poses, m.links, 1, m.poses.at(1)).found);
  planner.cancel();
  EXPECT_FALSE(planner.isActive());
  EXPECT_TRUE(planner.path().empty());
  EXPECT_TRUE(planner.goalPose().isNull());
  const PlanStatus s = planner.update(m.poses, m.poses.at(1));
  EXPECT_EQ(0, s.currentGoalId);
  EXPECT_TRUE(s.immune.empty());
  EXPECT_FALSE(s.failed);
}

}  // namespace
}  // namespace rtabmap
