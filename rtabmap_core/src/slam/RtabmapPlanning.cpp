// Path planning in the SLAM loop (SPLAM paper, Autonomous Robots 2017, 3.3.5): the planner
// (PathPlanner.h) works on plain poses and links; here it gets the whole map to plan on, and
// each update the local map to follow the path in, and its requests reach the memory.
#include "RtabmapImpl.h"
#include "rtabmap_core/optimizer/Graph.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap {

bool Rtabmap::Impl::setGoal(const PlanGoal& goal) {
  rejection.clear();
  goalReached = false;
  goalFailure.clear();
  const auto refuseGoal = [this](const std::string& why) {
    rejection = why;
    RTABMAP_WARN("goal refused: " << why);
    return false;
  };
  if (!initialized) return refuseGoal("no map: init() was not called");
  if (lastNodeId == 0 && currentPose.isNull()) return refuseGoal("the robot is not in the map yet (no update)");
  const std::map<int, Transform> poses = graph.posesOfGroup(mapId);
  std::multimap<int, Link> links;
  if (db) {
    db->flush();
    links = db->loadAllLinks(false);
  }
  // RAM holds links not saved yet; duplicates are filtered below.
  for (const auto& [from, link] : ramLinks(ramPosesOfGroup())) links.emplace(from, link);
  const PlanResult r = planner.plan(goal, poses, graph::filterDuplicateLinks(links), lastNodeId, currentPose);
  if (!r.found) return refuseGoal("no path to the goal: " + r.why);
  RTABMAP_INFO("planned a path of " << r.path.size() << " nodes to node " << r.goalNodeId << " (cost " << r.cost << ")");
  if (options.goalsSavedInUserData) saveGoalInUserData(r.goalNodeId);
  return true;
}

// RGBD/GoalsSavedInUserData, the original's text: the node where the robot was when it was
// given the goal remembers it, by label when the goal node has one.
void Rtabmap::Impl::saveGoalInUserData(int goalNodeId) {
  const auto label = labelCache.find(goalNodeId);
  std::string text = "GOAL:" + (label != labelCache.end() ? label->second : std::to_string(goalNodeId));
  const cv::Mat bytes = cv::Mat(1, static_cast<int>(text.size()), CV_8UC1, text.data()).clone();
  std::string why = "the robot is on no node";
  if (lastNodeId == 0 || !detector->memory().setUserData(lastNodeId, bytes, &why)) {
    RTABMAP_WARN(Parameters::kRGBDGoalsSavedInUserData() << ": \"" << text << "\" not saved: " << why);
  }
}

void Rtabmap::Impl::followPlan(int currentId, memory::LoopClosureUpdate& u, std::set<int>& immune) {
  if (!planner.isActive()) return;
  const PlanStatus status = planner.update(ramPosesOfGroup(), currentPose, currentId);
  stats.currentGoalId = status.currentGoalId;
  if (!status.toRetrieve.empty() && db) {
    const std::vector<int> back = detector->memory().retrieveIds(status.toRetrieve);
    u.retrieved.insert(u.retrieved.end(), back.begin(), back.end());
    immune.insert(back.begin(), back.end());
  }
  immune.insert(status.immune.begin(), status.immune.end());
  if (status.goalReached) {
    goalReached = true;
    RTABMAP_INFO("goal reached");
  } else if (status.failed) {
    goalFailure = status.why;
    RTABMAP_WARN("path planning failed: " << status.why);
  }
}

bool Rtabmap::setGoal(int nodeId) { return impl_->setGoal(PlanGoal::node(nodeId)); }

bool Rtabmap::setGoal(const std::string& label) {
  const int id = nodeOfLabel(label);
  if (id == 0) {
    impl_->rejection = "no node has the label \"" + label + "\"";
    RTABMAP_WARN("goal refused: " << impl_->rejection);
    return false;
  }
  return setGoal(id);
}

bool Rtabmap::setGoal(const Transform& pose) {
  if (pose.isNull() || pose.isInvalid()) {
    impl_->rejection = "the goal pose is null or not finite";
    RTABMAP_WARN("goal refused: " << impl_->rejection);
    return false;
  }
  return impl_->setGoal(PlanGoal::at(pose));
}

void Rtabmap::cancelGoal() { impl_->planner.cancel(); }
std::vector<std::pair<int, Transform>> Rtabmap::goalPath() const { return impl_->planner.path(); }
bool Rtabmap::goalReached() const { return impl_->goalReached; }
const std::string& Rtabmap::goalFailure() const { return impl_->goalFailure; }

}  // namespace rtabmap
