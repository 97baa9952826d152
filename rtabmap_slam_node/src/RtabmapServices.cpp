// rtabmap nodelet: the services (RtabmapNodelet.h). Each takes the core's lock, so a service
// never runs in the middle of an update.
#include <cstdio>

#include "RtabmapNodelet.h"

namespace rtabmap_ros {

bool RtabmapNodelet::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The map is deleted: close, remove the database, start again empty in the same mode.
  stopCore();
  if (!databasePath_.empty() && std::remove(databasePath_.c_str()) != 0) {
    NODELET_WARN("%s: reset: could not delete %s", getName().c_str(), databasePath_.c_str());
  }
  {
    std::lock_guard<std::mutex> tfLock(tfMutex_);
    mapToOdom_ = rtabmap::Transform::Identity();
  }
  NODELET_INFO("%s: reset: the map was deleted.", getName().c_str());
  return startCore(mapping_);
}

bool RtabmapNodelet::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (paused_) NODELET_WARN("%s: already paused.", getName().c_str());
  else NODELET_INFO("%s: paused.", getName().c_str());
  paused_ = true;
  return true;
}

bool RtabmapNodelet::onResume(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!paused_) NODELET_WARN("%s: was not paused.", getName().c_str());
  else NODELET_INFO("%s: resumed.", getName().c_str());
  paused_ = false;
  return true;
}

bool RtabmapNodelet::onTriggerNewMap(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!core_) return false;
  core_->triggerNewMap();
  NODELET_INFO("%s: a new map starts at the next update.", getName().c_str());
  return true;
}

// The core saves everything in RAM when it closes and has no separate flush: backup closes
// the database and reopens it, which starts a new session (a new map id) in the same
// database; the core merges it with the previous maps at the next loop closure or proximity
// link, as after any restart.
bool RtabmapNodelet::onBackup(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!core_) return false;
  if (databasePath_.empty()) {
    NODELET_WARN("%s: backup: no database (database_path is empty); nothing saved.", getName().c_str());
    return true;
  }
  stopCore();
  NODELET_INFO("%s: backup: everything saved to %s", getName().c_str(), databasePath_.c_str());
  return startCore(mapping_);
}

bool RtabmapNodelet::onSetModeLocalization(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!mapping_ && core_) {
    NODELET_INFO("%s: already in localization mode.", getName().c_str());
    return true;
  }
  if (databasePath_.empty()) {
    NODELET_ERROR("%s: localization needs a database (database_path is empty).", getName().c_str());
    return false;
  }
  stopCore();
  if (startCore(false)) return true;
  startCore(true);  // stay usable in the mode we had
  return false;
}

bool RtabmapNodelet::onSetModeMapping(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (mapping_ && core_) {
    NODELET_INFO("%s: already in mapping mode.", getName().c_str());
    return true;
  }
  stopCore();
  return startCore(true);
}

bool RtabmapNodelet::onGetMap(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!core_) return false;
  const rtabmap::GridMap grid = core_->gridMap();
  if (grid.empty()) {
    NODELET_WARN("%s: get_map: the occupancy grid is empty (RGBD/CreateOccupancyGrid false, or no node yet).",
                 getName().c_str());
    return false;
  }
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = mapFrameId_;
  res.map = rtabmap_slam_node::gridMapToMsg(grid, header);
  return true;
}

bool RtabmapNodelet::onSetLabel(rtabmap_ros::SetLabel::Request& req, rtabmap_ros::SetLabel::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!core_) return false;
  const int id = req.node_id > 0 ? req.node_id : core_->lastNodeId();
  if (id <= 0 || !core_->setLabel(id, req.node_label)) {
    NODELET_WARN("%s: set_label: cannot label node %d \"%s\" (unknown node, or the label names another node).",
                 getName().c_str(), id, req.node_label.c_str());
    return false;
  }
  NODELET_INFO("%s: node %d labelled \"%s\".", getName().c_str(), id, req.node_label.c_str());
  return true;
}

bool RtabmapNodelet::onListLabels(rtabmap_ros::ListLabels::Request&, rtabmap_ros::ListLabels::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!core_) return false;
  for (const auto& [id, label] : core_->labels()) {
    res.ids.push_back(id);
    res.labels.push_back(label);
  }
  return true;
}

}  // namespace rtabmap_ros
