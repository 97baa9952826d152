#pragma once
// Topological path planning over the map graph, as in the SPLAM paper (Labbe & Michaud,
// "Long-term online multi-session graph-based SPLAM with memory management", Autonomous Robots
// 2017, section 3.3.5). Plain data in, plain data out: no Memory, no database, no ROS.
//
// Why a graph planner: the map is too large to plan metric paths over all of it, and most of it
// is in Long-Term Memory (LTM). The planner therefore
//   1. plans a topological path once, by Dijkstra over every known node (LTM included, last
//      optimised poses) with the travel-time cost of the paper (graph::linkCost: distance /
//      RGBD/PlanLinearVelocity + heading change / RGBD/PlanAngularVelocity);
//   2. at each SLAM update, hands the metric local planner the "current goal": the farthest
//      node of the path, looking ahead from the robot's progress, that is in the local map and
//      within RGBD/LocalRadius of the robot;
//   3. says which upcoming path nodes to retrieve from LTM (Heuristic 2 of the paper: the nodes
//      of the path are retrieved before the robot gets there, at most RGBD/MaxLocalRetrieved per
//      update) and which upcoming nodes in RAM to immunise against transfer;
//   4. reports the goal reached (RGBD/GoalReachedRadius) or a failure after
//      RGBD/PlanStuckIterations updates without getting closer to the current goal.
//
// Usage by the SLAM pipeline:
//   PathPlanner planner(PlannerOptions::fromParameters(parameters));
//   PlanResult r = planner.plan(PlanGoal::node(id), allPoses, allLinks, lastId, robotPose);
//   each update: PlanStatus s = planner.update(localMapPoses, robotPose, lastId);
//                links = planner.temporaryLinks(localMapPoses, localMapLinks);
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/optimizer/Graph.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

struct PlannerOptions {
  float goalReachedRadius = 0.5f;  // RGBD/GoalReachedRadius (m)
  int stuckIterations = 0;         // RGBD/PlanStuckIterations (0 = never fail for being stuck)
  float linearVelocity = 0.0f;     // RGBD/PlanLinearVelocity (m/s, 0 = cost in metres)
  float angularVelocity = 0.0f;    // RGBD/PlanAngularVelocity (rad/s, 0 = turns are free)
  int maxRetrieved = 2;            // RGBD/MaxLocalRetrieved (path nodes asked from LTM per update)
  float localRadius = 10.0f;       // RGBD/LocalRadius (m): look-ahead of the current goal
  bool is2D = false;               // Reg/Force3DoF: distances and turns in the plane

  static PlannerOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

// A goal: a node id (a label is resolved to its node id by the caller), or a metric pose in the
// map frame. For a pose, the goal node is the node nearest to it among the nodes reachable from
// the robot (nodes of other components have poses in another referential), and the final goal
// is the pose itself, kept relative to that node so it follows the node when the graph is
// re-optimised.
struct PlanGoal {
  int nodeId = 0;
  Transform pose;  // null for a node goal

  static PlanGoal node(int id) { return PlanGoal{id, Transform()}; }
  static PlanGoal at(const Transform& pose) { return PlanGoal{0, pose}; }
};

struct PlanResult {
  bool found = false;
  std::string why;  // if not found, in words
  int goalNodeId = 0;
  double cost = 0.0;  // Dijkstra cost (m, or s with velocities)
  // Start node ... goal node with the poses the path was planned on.
  std::vector<std::pair<int, Transform>> path;
};

struct PlanStatus {
  // Farthest node of the path ahead that is in the local map and within RGBD/LocalRadius of the
  // robot (0 if none: the path ahead is not in the local map yet); its local-map pose, or the
  // final metric goal when it is the last node of a pose goal.
  int currentGoalId = 0;
  Transform currentGoalPose;
  // Path node the robot has reached (nearest node, never going back along the path).
  int progressNodeId = 0;
  // Upcoming path nodes absent from the local map, in path order, at most RGBD/MaxLocalRetrieved.
  std::vector<int> toRetrieve;
  // Upcoming path nodes present in the local map: keep them out of transfer.
  std::set<int> immune;
  bool goalReached = false;  // the plan is over (inactive) when reached or failed
  bool failed = false;
  std::string why;  // why it failed
};

class PathPlanner {
 public:
  explicit PathPlanner(const PlannerOptions& options = PlannerOptions());

  // Plans a new path, replacing the current one (also when it fails: no plan is active then).
  // allPoses: every known node (LTM included) with its last optimised pose; allLinks: their
  // links (landmark links are ignored: a landmark is seen from places, it is not a place).
  // The path starts at currentNodeId, or at the node nearest to robotPose when currentNodeId is
  // not in allPoses (e.g. localization mode before the first localization).
  PlanResult plan(const PlanGoal& goal, const graph::Poses& allPoses, const graph::Links& allLinks,
                  int currentNodeId, const Transform& robotPose);

  // One SLAM update. localMapPoses: the nodes in RAM with their optimised poses (the local map);
  // robotPose: the robot in the same frame. currentNodeId is the newest node: if it is a node of
  // the path ahead, progress jumps to it. Inactive planner: empty status.
  PlanStatus update(const graph::Poses& localMapPoses, const Transform& robotPose,
                    int currentNodeId = 0);

  // Links of type kVirtualClosure that keep the path ahead connected in the local map. Take the
  // upcoming path nodes (from the progress node on) that are in localMapPoses, in path order;
  // for each two consecutive ones (a, b) that have no link between them in localMapLinks
  // (either direction, any type), one link a -> b whose transform is b's pose relative to a's
  // in the poses the path was planned on, with a weak information matrix (kVirtualInformation
  // on the diagonal) so that it connects without bending the graph. This happens when the path
  // nodes between a and b are in LTM (the local map has a gap), or when the caller's local links
  // lack the link of two adjacent path nodes. Not stored anywhere: ask again each update.
  std::vector<Link> temporaryLinks(const graph::Poses& localMapPoses,
                                   const graph::Links& localMapLinks) const;
  static constexpr double kVirtualInformation = 1e-2;  // sigma 10 m, 10 rad

  void cancel();
  // Mem/ReduceGraph: node `from` was merged into `to`, the same place: the path goes through
  // `to` instead (once, where they were consecutive), keeping the pose it was planned with.
  void renameNode(int from, int to);
  bool isActive() const { return !path_.empty(); }
  const std::vector<std::pair<int, Transform>>& path() const { return path_; }
  int goalId() const { return path_.empty() ? 0 : path_.back().first; }
  // Final metric goal in the planned poses (the goal node's pose for a node goal); null if
  // inactive.
  Transform goalPose() const;
  // Path nodes given up on after RGBD/PlanStuckIterations updates without getting closer.
  const std::set<int>& unreachableNodes() const { return unreachable_; }
  const PlannerOptions& options() const { return options_; }

 private:
  // Pose of path node i: its local-map pose if it is in the local map, else the planned one.
  Transform nodePose(std::size_t i, const graph::Poses& localMapPoses) const;
  Transform finalGoalPose(const graph::Poses& localMapPoses) const;
  // Metric goal of path index i: the final goal for the last node, else the node's pose.
  Transform goalPoseAt(int i, const graph::Poses& localMapPoses) const;
  void advanceProgress(const graph::Poses& localMapPoses, const Transform& robotPose,
                       int currentNodeId);
  // Index of the current goal, or -1 if no node ahead qualifies.
  int selectGoal(const graph::Poses& localMapPoses, const Transform& robotPose) const;
  // Counts an update without progress toward `goalIndex`; true when RGBD/PlanStuckIterations
  // is reached.
  bool stuckOn(int goalIndex, double distance);
  int goalAfterStuckCheck(const graph::Poses& localMapPoses, const Transform& robotPose,
                          std::string* why);
  void fillRetrievalAndImmunity(const graph::Poses& localMapPoses, PlanStatus* status) const;
  PlanStatus end(PlanStatus status);

  PlannerOptions options_;
  std::vector<std::pair<int, Transform>> path_;
  Transform goalOffset_;      // final goal relative to the last path node (identity for a node)
  std::size_t progress_ = 0;  // index of the path node the robot has reached
  std::set<int> unreachable_;
  static constexpr int kNoGoalYet = -2;
  int stuckGoal_ = kNoGoalYet;  // goal index the stuck counter is about (-1: no goal)
  double stuckBest_ = 0.0;    // smallest distance to it so far
  int stuckCount_ = 0;
};

}  // namespace rtabmap
