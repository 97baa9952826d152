// rtabmap nodelet: goals (RtabmapNodelet.h). The core plans a topological path through the
// graph (SPLAM paper) and follows it during the updates; here goals come in from the topics and
// services, and the path and the outcome go out.
#include <nav_msgs/Path.h>
#include <rtabmap_ros/Path.h>
#include <std_msgs/Bool.h>

#include <chrono>

#include "RtabmapNodelet.h"
#include "rtabmap_conversions/TfLookup.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_slam_node/MapViews.h"

namespace rtabmap_ros {

std_msgs::Header RtabmapNodelet::mapHeader(const ros::Time& stamp) const {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = mapFrameId_;
  return header;
}

bool RtabmapNodelet::haveCore(const char* service) {
  if (core_) return true;
  NODELET_WARN("%s: %s: no SLAM core (the database or parameters could not be used; see the errors above).",
               getName().c_str(), service);
  return false;
}

rtabmap::Transform RtabmapNodelet::poseInMap(const geometry_msgs::PoseStamped& goal, std::string* error) const {
  const rtabmap::Transform pose = rtabmap_conversions::transformFromPoseMsg(goal.pose);
  if (pose.isNull() || pose.isInvalid()) {
    *error = "the pose is not finite or its quaternion is zero";
    return rtabmap::Transform();
  }
  if (goal.header.frame_id.empty() || goal.header.frame_id == mapFrameId_) return pose;
  // Latest transform: a goal is where to go now, whatever its stamp.
  const rtabmap::Transform toMap = rtabmap_conversions::lookupTransform(*tfBuffer_, mapFrameId_, goal.header.frame_id,
                                                                      ros::Time(0), waitForTransform_, error);
  return toMap.isNull() ? rtabmap::Transform() : toMap * pose;
}

void RtabmapNodelet::onGoal(const geometry_msgs::PoseStampedConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("goal")) return;
  std::string error;
  const rtabmap::Transform pose = poseInMap(*msg, &error);
  if (pose.isNull()) {
    NODELET_WARN("%s: goal ignored: %s.", getName().c_str(), error.c_str());
    return;
  }
  if (!core_->setGoal(pose)) {
    NODELET_WARN("%s: goal at %s refused: %s", getName().c_str(), pose.prettyPrint().c_str(),
                 core_->lastRejection().c_str());
  } else {
    NODELET_INFO("%s: goal at %s: path of %zu nodes.", getName().c_str(), pose.prettyPrint().c_str(),
                 core_->goalPath().size());
  }
  publishGoalPath(ros::Time::now());
}

void RtabmapNodelet::onGoalNode(const rtabmap_ros::GoalConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("goal_node")) return;
  setGoalNode(msg->node_id, msg->node_label, "goal_node");
  publishGoalPath(ros::Time::now());
}

bool RtabmapNodelet::setGoalNode(int nodeId, const std::string& label, const char* from) {
  if (nodeId == 0 && label.empty()) {
    NODELET_WARN("%s: %s: neither a node id nor a label.", getName().c_str(), from);
    return false;
  }
  const bool ok = nodeId != 0 ? core_->setGoal(nodeId) : core_->setGoal(label);
  const std::string what = nodeId != 0 ? "node " + std::to_string(nodeId) : "label \"" + label + "\"";
  if (!ok) {
    NODELET_WARN("%s: %s: goal %s refused: %s", getName().c_str(), from, what.c_str(), core_->lastRejection().c_str());
    return false;
  }
  NODELET_INFO("%s: %s: goal %s, path of %zu nodes.", getName().c_str(), from, what.c_str(), core_->goalPath().size());
  return true;
}

bool RtabmapNodelet::onSetGoal(rtabmap_ros::SetGoal::Request& req, rtabmap_ros::SetGoal::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("set_goal")) return false;
  if (!req.frame_id.empty() && req.frame_id != mapFrameId_) {
    NODELET_WARN("%s: set_goal: paths are in %s; frame_id \"%s\" is not supported.", getName().c_str(),
                 mapFrameId_.c_str(), req.frame_id.c_str());
    return false;
  }
  const auto start = std::chrono::steady_clock::now();
  const bool ok = setGoalNode(req.node_id, req.node_label, "set_goal");
  res.planning_time = std::chrono::duration<float>(std::chrono::steady_clock::now() - start).count();
  publishGoalPath(ros::Time::now());
  if (!ok) return false;
  for (const auto& [id, pose] : rtabmap_slam_node::refreshPath(core_->goalPath(), core_->optimizedPoses())) {
    res.path_ids.push_back(id);
    res.path_poses.push_back(rtabmap_conversions::transformToPoseMsg(pose));
  }
  return true;
}

bool RtabmapNodelet::onCancelGoal(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("cancel_goal")) return false;
  if (core_->goalPath().empty()) NODELET_INFO("%s: cancel_goal: there was no goal.", getName().c_str());
  core_->cancelGoal();
  publishGoalPath(ros::Time::now());
  return true;
}

bool RtabmapNodelet::onGetPlan(rtabmap_ros::GetPlan::Request& req, rtabmap_ros::GetPlan::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("get_plan")) return false;
  std::string why;
  rtabmap::Transform goalPose;
  rtabmap_slam_node::NodePath path;
  if (req.goal_node != 0) {
    path = core_->planPath(req.goal_node, &why);
  } else {
    goalPose = poseInMap(req.goal, &why);
    if (!goalPose.isNull()) path = core_->planPath(goalPose, &why);
  }
  if (path.empty()) {
    NODELET_WARN("%s: get_plan: no plan: %s", getName().c_str(), why.c_str());
    return false;
  }
  path = rtabmap_slam_node::refreshPath(path, core_->optimizedPoses());
  if (!goalPose.isNull()) {
    const double distance = goalPose.getDistance(path.back().second);
    if (req.tolerance > 0.0f && distance > req.tolerance) {
      NODELET_WARN("%s: get_plan: the nearest node (%d) is %.2f m from the goal, more than the tolerance %.2f m.",
                   getName().c_str(), path.back().first, distance, req.tolerance);
      return false;
    }
    path.emplace_back(0, goalPose);  // the last waypoint is the goal itself
  }
  res.plan = rtabmap_slam_node::pathToMsg(path, mapHeader(ros::Time::now()));
  return true;
}

void RtabmapNodelet::publishGoalPath(const ros::Time& stamp) {
  rtabmap_slam_node::NodePath path = core_ ? core_->goalPath() : rtabmap_slam_node::NodePath();
  if (path.empty() && !goalPathShown_) return;  // nothing to show and nothing to clear
  if (!path.empty()) path = rtabmap_slam_node::refreshPath(path, core_->optimizedPoses());
  goalPathShown_ = !path.empty();
  const std_msgs::Header header = mapHeader(stamp);
  const nav_msgs::Path msg = rtabmap_slam_node::pathToMsg(path, header);
  mapPathPub_.publish(msg);
  globalPathPub_.publish(msg);
  rtabmap_ros::Path nodes;
  nodes.header = header;
  for (const auto& [id, pose] : path) {
    nodes.nodeIds.push_back(id);
    nodes.poses.push_back(rtabmap_conversions::transformToPoseMsg(pose));
  }
  globalPathNodesPub_.publish(nodes);
}

void RtabmapNodelet::publishGoalStatus(const ros::Time& stamp) {
  const bool reached = core_->goalReached();
  const std::string& failure = core_->goalFailure();
  if (reached || !failure.empty()) {
    std_msgs::Bool msg;
    msg.data = reached;
    goalReachedPub_.publish(msg);
    if (reached) {
      NODELET_INFO("%s: goal reached.", getName().c_str());
    } else {
      NODELET_WARN("%s: goal failed: %s", getName().c_str(), failure.c_str());
    }
  }
  // The path moves with the map while it lasts, and is cleared when it ends.
  publishGoalPath(stamp);
}

}  // namespace rtabmap_ros
