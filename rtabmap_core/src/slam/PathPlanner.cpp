// PathPlanner: topological path by Dijkstra, then per-update current goal, retrieval, immunity
// and end conditions (SPLAM paper, section 3.3.5). See the header for the contract.
#include "rtabmap_core/slam/PathPlanner.h"

#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

std::string str(int id) { return std::to_string(id); }

// The nodes (positive ids: landmarks are negative) with a usable pose.
graph::Poses placesOf(const graph::Poses& poses) {
  graph::Poses places;
  for (const auto& [id, pose] : poses) {
    if (id > 0 && !pose.isNull()) places.emplace_hint(places.end(), id, pose);
  }
  return places;
}

std::set<int> idsOf(const graph::Poses& poses) {
  std::set<int> ids;
  for (const auto& entry : poses) ids.insert(ids.end(), entry.first);
  return ids;
}

graph::Poses restrictTo(const graph::Poses& poses, const std::set<int>& ids) {
  graph::Poses out;
  for (const auto& [id, pose] : poses) {
    if (ids.count(id)) out.emplace_hint(out.end(), id, pose);
  }
  return out;
}

}  // namespace

// ---- Options ------------------------------------------------------------------------------------

PlannerOptions PlannerOptions::fromParameters(const ParametersMap& parameters) {
  PlannerOptions o;
  o.goalReachedRadius = Parameters::getFloat(parameters, Parameters::kRGBDGoalReachedRadius());
  o.stuckIterations = Parameters::getInt(parameters, Parameters::kRGBDPlanStuckIterations());
  o.linearVelocity = Parameters::getFloat(parameters, Parameters::kRGBDPlanLinearVelocity());
  o.angularVelocity = Parameters::getFloat(parameters, Parameters::kRGBDPlanAngularVelocity());
  o.maxRetrieved = Parameters::getInt(parameters, Parameters::kRGBDMaxLocalRetrieved());
  o.localRadius = Parameters::getFloat(parameters, Parameters::kRGBDLocalRadius());
  o.is2D = Parameters::getBool(parameters, Parameters::kRegForce3DoF());
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool PlannerOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (!(goalReachedRadius > 0.0f)) return fail(Parameters::kRGBDGoalReachedRadius() + " must be positive");
  if (stuckIterations < 0) return fail(Parameters::kRGBDPlanStuckIterations() + " must be 0 (disabled) or more");
  if (!(linearVelocity >= 0.0f)) return fail(Parameters::kRGBDPlanLinearVelocity() + " must be 0 or more");
  if (!(angularVelocity >= 0.0f)) return fail(Parameters::kRGBDPlanAngularVelocity() + " must be 0 or more");
  if (maxRetrieved < 0) return fail(Parameters::kRGBDMaxLocalRetrieved() + " must be 0 (disabled) or more");
  if (!(localRadius > 0.0f)) return fail(Parameters::kRGBDLocalRadius() + " must be positive");
  return true;
}

// ---- Planning -----------------------------------------------------------------------------------

PathPlanner::PathPlanner(const PlannerOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("PathPlanner: " + why);
}

void PathPlanner::cancel() {
  path_.clear();
  goalOffset_ = Transform::Identity();
  progress_ = 0;
  unreachable_.clear();
  stuckGoal_ = kNoGoalYet;
  stuckBest_ = 0.0;
  stuckCount_ = 0;
}

void PathPlanner::renameNode(int from, int to) {
  if (from == to) return;
  std::vector<std::pair<int, Transform>> renamed;
  std::size_t progress = 0;
  for (std::size_t i = 0; i < path_.size(); ++i) {
    const int id = path_[i].first == from ? to : path_[i].first;
    if (!renamed.empty() && renamed.back().first == id) {
      if (i == progress_) progress = renamed.size() - 1;  // the kept one is where the robot is
      if (i + 1 == path_.size()) renamed.back().second = path_[i].second;  // the goal's planned pose
      continue;
    }
    if (i == progress_) progress = renamed.size();
    renamed.emplace_back(id, path_[i].second);
  }
  path_.swap(renamed);
  progress_ = progress;
  if (unreachable_.erase(from)) unreachable_.insert(to);
}

PlanResult PathPlanner::plan(const PlanGoal& goal, const graph::Poses& allPoses,
                             const graph::Links& allLinks, int currentNodeId,
                             const Transform& robotPose) {
  cancel();
  PlanResult result;
  auto fail = [&result](const std::string& why) {
    result.why = why;
    return result;
  };
  if (goal.nodeId != 0 && !goal.pose.isNull()) return fail("a goal is a node id or a pose, not both");
  if (goal.nodeId == 0 && goal.pose.isNull()) return fail("no goal given (node id 0 and no pose)");
  if (goal.pose.isInvalid()) return fail("the goal pose has NaN or infinite values");

  const graph::Poses places = placesOf(allPoses);
  // A landmark is seen from several places but is not a place the robot can go through.
  const graph::Links links = graph::filterLinks(allLinks, Link::kLandmark);

  int start = places.count(currentNodeId) ? currentNodeId : 0;
  if (start == 0 && !robotPose.isNull() && !robotPose.isInvalid()) {
    start = graph::findNearestNode(places, robotPose, nullptr, options_.is2D);
  }
  if (start == 0) {
    return fail("cannot locate the robot in the map: node " + str(currentNodeId) +
                " has no pose and no robot pose was given");
  }
  const std::set<int> allowed = idsOf(places);
  const std::set<int> reachable = graph::connectedComponent(start, links, &allowed);

  int target = goal.nodeId;
  Transform offset = Transform::Identity();
  if (goal.nodeId != 0) {
    if (!places.count(target)) return fail("goal node " + str(target) + " is unknown (not in the map)");
    if (!reachable.count(target)) {
      return fail("goal node " + str(target) + " is not connected to the robot's node " + str(start) +
                  " (it is in another map that no loop closure links to this one)");
    }
  } else {
    // Nodes of other components live in another referential: their poses mean nothing here.
    target = graph::findNearestNode(restrictTo(places, reachable), goal.pose, nullptr, options_.is2D);
    offset = places.at(target).inverse() * goal.pose;
  }

  const graph::PathCost cost{options_.linearVelocity, options_.angularVelocity, options_.is2D};
  const graph::Path path = graph::computePath(places, links, start, target, cost);
  if (!path.found) return fail("no path from node " + str(start) + " to goal node " + str(target));

  path_ = path.nodes;
  goalOffset_ = offset;
  result.found = true;
  result.goalNodeId = target;
  result.cost = path.cost;
  result.path = path_;
  return result;
}

Transform PathPlanner::goalPose() const {
  return path_.empty() ? Transform() : path_.back().second * goalOffset_;
}

// ---- Following ----------------------------------------------------------------------------------

Transform PathPlanner::nodePose(std::size_t i, const graph::Poses& localMapPoses) const {
  const auto it = localMapPoses.find(path_[i].first);
  return it != localMapPoses.end() && !it->second.isNull() ? it->second : path_[i].second;
}

Transform PathPlanner::finalGoalPose(const graph::Poses& localMapPoses) const {
  return nodePose(path_.size() - 1, localMapPoses) * goalOffset_;
}

Transform PathPlanner::goalPoseAt(int i, const graph::Poses& localMapPoses) const {
  return static_cast<std::size_t>(i) + 1 == path_.size() ? finalGoalPose(localMapPoses)
                                                         : nodePose(i, localMapPoses);
}

// Progress = the path node nearest to the robot among the nodes of the local map within
// RGBD/LocalRadius of path length ahead of the current progress. The window keeps a path that
// folds back near itself from jumping ahead; progress never decreases (the robot does not go
// back along the path, even if it drifts back).
void PathPlanner::advanceProgress(const graph::Poses& localMapPoses, const Transform& robotPose,
                                  int currentNodeId) {
  double along = 0.0;
  double nearest = -1.0;
  std::size_t best = progress_;
  for (std::size_t i = progress_; i < path_.size(); ++i) {
    const Transform pose = nodePose(i, localMapPoses);
    if (i > progress_) along += graph::poseDistance(nodePose(i - 1, localMapPoses), pose, options_.is2D);
    if (along > options_.localRadius) break;
    if (path_[i].first == currentNodeId) {  // the robot is on that node itself
      best = i;
      break;
    }
    if (!localMapPoses.count(path_[i].first)) continue;
    const double d = graph::poseDistance(robotPose, pose, options_.is2D);
    if (nearest < 0.0 || d < nearest) {
      nearest = d;
      best = i;
    }
  }
  progress_ = best;
}

// The farthest node ahead that the local planner can reach through known space: from the
// progress node on, while the path length from the robot stays within RGBD/LocalRadius (so its
// Euclidean distance does too) and every node on the way is in the local map (beyond a node in
// LTM the local map does not know the way). Nodes given up on are skipped.
int PathPlanner::selectGoal(const graph::Poses& localMapPoses, const Transform& robotPose) const {
  int goal = -1;
  double along = graph::poseDistance(robotPose, nodePose(progress_, localMapPoses), options_.is2D);
  for (std::size_t i = progress_; i < path_.size(); ++i) {
    if (i > progress_) {
      along += graph::poseDistance(nodePose(i - 1, localMapPoses), nodePose(i, localMapPoses), options_.is2D);
    }
    if (along > options_.localRadius || !localMapPoses.count(path_[i].first)) break;
    if (!unreachable_.count(path_[i].first)) goal = static_cast<int>(i);
  }
  return goal;
}

// "No progress" = the distance to the same goal did not get below its smallest value so far
// (so odometry noise around a blocked position does not reset the count). A new goal (the
// robot advanced, or a node was given up on) starts counting afresh; with no goal at all
// (index -1, the path ahead is not in the local map) every update counts.
bool PathPlanner::stuckOn(int goalIndex, double distance) {
  if (options_.stuckIterations <= 0) return false;
  if (goalIndex != stuckGoal_) {
    stuckGoal_ = goalIndex;
    stuckBest_ = distance;
    stuckCount_ = 0;
    return false;
  }
  if (goalIndex >= 0 && distance < stuckBest_) {
    stuckBest_ = distance;
    stuckCount_ = 0;
    return false;
  }
  return ++stuckCount_ >= options_.stuckIterations;
}

void PathPlanner::fillRetrievalAndImmunity(const graph::Poses& localMapPoses, PlanStatus* status) const {
  for (std::size_t i = progress_; i < path_.size(); ++i) {
    const int id = path_[i].first;
    if (localMapPoses.count(id)) {
      status->immune.insert(id);
    } else if (static_cast<int>(status->toRetrieve.size()) < options_.maxRetrieved) {
      status->toRetrieve.push_back(id);
    }
  }
}

PlanStatus PathPlanner::end(PlanStatus status) {
  cancel();
  return status;
}

// The goal of this update after RGBD/PlanStuckIterations: a goal node without progress for that
// many updates is given up on for the next best one; -1 with *why set when none is left. Being
// at an intermediate goal (waiting for the next nodes to be retrieved) is not being stuck.
int PathPlanner::goalAfterStuckCheck(const graph::Poses& localMapPoses, const Transform& robotPose,
                                     std::string* why) {
  int goal = selectGoal(localMapPoses, robotPose);
  const double distance =
      goal >= 0 ? graph::poseDistance(robotPose, goalPoseAt(goal, localMapPoses), options_.is2D) : 0.0;
  const bool arrived = goal >= 0 && distance <= options_.goalReachedRadius;
  if (arrived || !stuckOn(goal, distance)) return goal;
  if (goal < 0) {
    *why = "the path ahead (next node " + str(path_[progress_].first) + ") has not been in the local map for " +
           str(options_.stuckIterations) + " updates";
    return -1;
  }
  const int given = path_[goal].first;
  unreachable_.insert(given);
  goal = selectGoal(localMapPoses, robotPose);
  if (goal < 0) {
    *why = "no progress toward node " + str(given) + " of the path for " + str(options_.stuckIterations) +
           " updates, and no other node of the path ahead is in the local map within " +
           Parameters::kRGBDLocalRadius();
    return -1;
  }
  stuckOn(goal, graph::poseDistance(robotPose, goalPoseAt(goal, localMapPoses), options_.is2D));
  return goal;
}

PlanStatus PathPlanner::update(const graph::Poses& localMapPoses, const Transform& robotPose,
                               int currentNodeId) {
  PlanStatus status;
  if (!isActive()) return status;
  if (robotPose.isNull() || robotPose.isInvalid()) {  // odometry lost: nothing to judge this time
    fillRetrievalAndImmunity(localMapPoses, &status);
    status.progressNodeId = path_[progress_].first;
    return status;
  }
  advanceProgress(localMapPoses, robotPose, currentNodeId);
  status.progressNodeId = path_[progress_].first;

  const Transform finalGoal = finalGoalPose(localMapPoses);
  if (graph::poseDistance(robotPose, finalGoal, options_.is2D) <= options_.goalReachedRadius) {
    status.goalReached = true;
    status.currentGoalId = goalId();
    status.currentGoalPose = finalGoal;
    return end(status);
  }
  fillRetrievalAndImmunity(localMapPoses, &status);
  const int goal = goalAfterStuckCheck(localMapPoses, robotPose, &status.why);
  if (!status.why.empty()) {
    status.failed = true;
    return end(status);
  }
  if (goal >= 0) {
    status.currentGoalId = path_[goal].first;
    status.currentGoalPose = goalPoseAt(goal, localMapPoses);
  }
  return status;
}

// ---- Virtual links ------------------------------------------------------------------------------

std::vector<Link> PathPlanner::temporaryLinks(const graph::Poses& localMapPoses,
                                              const graph::Links& localMapLinks) const {
  std::vector<Link> links;
  const Link::InfMatrix information = Link::InfMatrix::Identity() * kVirtualInformation;
  int previous = -1;  // index of the previous upcoming path node in the local map
  for (std::size_t i = progress_; i < path_.size(); ++i) {
    if (!localMapPoses.count(path_[i].first)) continue;
    if (previous >= 0) {
      const auto& [a, poseA] = path_[previous];
      const auto& [b, poseB] = path_[i];
      if (a != b && graph::findLink(localMapLinks, a, b) == localMapLinks.end()) {
        links.emplace_back(a, b, Link::kVirtualClosure, poseA.inverse() * poseB, information);
      }
    }
    previous = static_cast<int>(i);
  }
  return links;
}

}  // namespace rtabmap
