// rtabmap nodelet: the services (RtabmapNodelet.h). Each takes the core's lock, so a service
// never runs in the middle of an update.
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "RtabmapNodelet.h"
#include "rtabmap_conversions/GraphConversions.h"
#include "rtabmap_slam_node/ServicePaths.h"
#include "rtabmap_slam_node/SlamNodeSupport.h"

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
  publishMarkers(ros::Time::now());
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

bool RtabmapNodelet::onRemoveLabel(rtabmap_ros::RemoveLabel::Request& req, rtabmap_ros::RemoveLabel::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("remove_label")) return false;
  if (req.label.empty()) {
    NODELET_WARN("%s: remove_label: the label is empty.", getName().c_str());
    return false;
  }
  const int id = core_->nodeOfLabel(req.label);
  if (id == 0) {
    NODELET_WARN("%s: remove_label: no node has the label \"%s\".", getName().c_str(), req.label.c_str());
    return false;
  }
  if (!core_->setLabel(id, "")) {
    NODELET_WARN("%s: remove_label: cannot change node %d (localization mode does not modify the map).",
                 getName().c_str(), id);
    return false;
  }
  NODELET_INFO("%s: label \"%s\" removed from node %d.", getName().c_str(), req.label.c_str(), id);
  publishMarkers(ros::Time::now());
  return true;
}

bool RtabmapNodelet::onAddLink(rtabmap_ros::AddLink::Request& req, rtabmap_ros::AddLink::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("add_link")) return false;
  std::string why;
  std::optional<rtabmap::Link> link = rtabmap_conversions::linkFromMsg(req.link, &why);
  if (link && link->infMatrix().diagonal().minCoeff() <= 0.0) {
    why = "the information matrix must have a positive diagonal (inverse variances of x y z roll pitch yaw)";
    link.reset();
  }
  if (!link || !core_->addLink(*link)) {
    NODELET_WARN("%s: add_link %d -> %d refused: %s", getName().c_str(), req.link.fromId, req.link.toId,
                 link ? core_->lastRejection().c_str() : why.c_str());
    return false;
  }
  {
    std::lock_guard<std::mutex> tfLock(tfMutex_);
    mapToOdom_ = core_->mapCorrection();
  }
  NODELET_INFO("%s: user link %d -> %d added; the map was re-optimised.", getName().c_str(), link->from(), link->to());
  const ros::Time now = ros::Time::now();
  publishMarkers(now);
  publishGoalPath(now);
  if (gridMapPub_.getNumSubscribers() > 0) publishGrid(now);
  return true;
}

bool RtabmapNodelet::restartCore(const std::string& previousPath, const rtabmap::ParametersMap& previousParameters) {
  stopCore();
  if (!startCore(mapping_)) {
    NODELET_WARN("%s: going back to \"%s\" with the previous parameters.", getName().c_str(), previousPath.c_str());
    databasePath_ = previousPath;
    parameters_ = previousParameters;
    startCore(mapping_);
    return false;
  }
  std::lock_guard<std::mutex> tfLock(tfMutex_);
  mapToOdom_ = core_->mapCorrection();
  return true;
}

bool RtabmapNodelet::onUpdateParameters(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  const rtabmap::ParametersMap previous = parameters_;
  parameters_ = readCoreParameters(getPrivateNodeHandle());
  // The mode stays what the services made it; a Mem/IncrementalMemory parameter switches it.
  if (parameters_.count("Mem/IncrementalMemory")) {
    mapping_ = rtabmap::Parameters::getBool(parameters_, "Mem/IncrementalMemory");
    parameters_.erase("Mem/IncrementalMemory");
  }
  if (!restartCore(databasePath_, previous)) return false;
  NODELET_INFO("%s: update_parameters: %zu core parameters applied.", getName().c_str(), parameters_.size());
  return true;
}

bool RtabmapNodelet::onLoadDatabase(rtabmap_ros::LoadDatabase::Request& req, rtabmap_ros::LoadDatabase::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Anyone on the ROS graph can call this, and clear deletes the file: the path is confined to
  // database_directory before anything is closed or deleted.
  std::string why = "database_directory does not exist";
  const std::optional<std::string> path =
      serviceDirectory_.empty()
          ? std::nullopt
          : rtabmap_slam_node::confinedPath(rtabmap_slam_node::expandHome(req.database_path), serviceDirectory_, &why);
  if (!path) {
    NODELET_ERROR("%s: load_database refused: %s. The current database is kept.", getName().c_str(), why.c_str());
    return false;
  }
  const std::string previous = databasePath_;
  stopCore();  // the current map is saved before anything is deleted
  if (req.clear && std::remove(path->c_str()) != 0 && errno != ENOENT) {
    NODELET_WARN("%s: load_database: cannot delete %s: %s", getName().c_str(), path->c_str(), std::strerror(errno));
  }
  databasePath_ = *path;
  const bool ok = restartCore(previous, parameters_);
  if (ok) NODELET_INFO("%s: load_database: now on \"%s\"%s.", getName().c_str(), path->c_str(), req.clear ? " (cleared)" : "");
  return ok;
}

}  // namespace rtabmap_ros
