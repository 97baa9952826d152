// rtabmap nodelet: the map for other nodes (RtabmapNodelet.h): mapData (incremental, or the
// whole map on request), node data by id, nodes near a place, the rviz marker views and the 3D
// maps (cloud_map, octomap_*).
#include <visualization_msgs/MarkerArray.h>

#include <set>

#include "RtabmapNodelet.h"
#include "rtabmap_conversions/NodeDataConversions.h"
#include "rtabmap_conversions/TransformConversions.h"
#include "rtabmap_slam_node/MapViews.h"

namespace rtabmap_ros {

void RtabmapNodelet::publishMarkers(const ros::Time& stamp, bool force) {
  const bool labels = force || labelsPub_.getNumSubscribers() > 0;
  const bool graph = force || graphMarkersPub_.getNumSubscribers() > 0;
  if (!core_ || (!labels && !graph)) return;
  const std::map<int, rtabmap::Transform> poses = core_->optimizedPoses();
  const std_msgs::Header header = mapHeader(stamp);
  if (labels) labelsPub_.publish(rtabmap_slam_node::labelMarkers(core_->labels(), poses, header));
  if (graph) {
    std::map<int, rtabmap::Transform> withLandmarks = poses;
    const std::map<int, rtabmap::Transform> landmarks = core_->landmarkPoses();
    withLandmarks.insert(landmarks.begin(), landmarks.end());
    graphMarkersPub_.publish(rtabmap_slam_node::graphMarkers(withLandmarks, core_->allLinks(), header));
  }
}

void RtabmapNodelet::publishLatestNodeData(const ros::Time& stamp) {
  // The graph as mapGraph has it, and the data of the node this update added (none in
  // localization mode or when the update only rehearsed): a listener accumulates the nodes.
  // Rtabmap/PublishLastSignature false: the graph alone, for a remote viewer on a thin link
  // (get_node_data gives the nodes it wants).
  std::map<int, rtabmap::Signature> nodes;
  const int id = core_->statistics().refImageId;
  if (id > 0 && rtabmap::Parameters::getBool(parameters_, rtabmap::Parameters::kRtabmapPublishLastSignature())) {
    if (std::optional<rtabmap::Signature> s = core_->node(id)) nodes.emplace(id, std::move(*s));
  }
  mapDataPub_.publish(rtabmap_conversions::mapDataToMsg(core_->optimizedPoses(), core_->allLinks(), nodes,
                                                        core_->mapCorrection(), mapHeader(stamp)));
}

void RtabmapNodelet::publishMaps(const ros::Time& stamp, bool force) {
  if (!core_) return;
  // Under mutex_: the poses and the grids the maps worker has not received yet (one per update
  // in steady state); it assembles and publishes on its own thread.
  maps_.submit(core_->optimizedPoses(), [this](int id) { return localGridOf(id); }, mapHeader(stamp), force);
}

void RtabmapNodelet::onMapSubscriber() {
  std::lock_guard<std::mutex> lock(mutex_);
  publishMaps(ros::Time::now(), true);
}

std::optional<rtabmap::LocalGrid> RtabmapNodelet::localGridOf(int nodeId) const {
  rtabmap::NodeDataParts gridOnly;
  gridOnly.images = gridOnly.scan = gridOnly.userData = false;
  std::optional<rtabmap::Signature> s = core_->node(nodeId, gridOnly);  // from RAM or the database
  if (!s) return std::nullopt;
  return s->sensorData().localGrid();
}

rtabmap_ros::MapData RtabmapNodelet::mapDataOf(bool global, bool optimized, bool graphOnly,
                                               const ros::Time& stamp) const {
  std::vector<int> ids = global ? core_->allNodeIds() : core_->workingMemory();
  const std::set<int> wanted(ids.begin(), ids.end());
  std::map<int, rtabmap::Transform> poses;
  std::map<int, rtabmap::Signature> nodes;
  if (optimized) {
    // Optimised poses exist for the current referential only.
    for (const auto& [id, pose] : core_->optimizedPoses()) {
      if (wanted.count(id)) poses.emplace(id, pose);
    }
  }
  rtabmap::NodeDataParts parts;
  if (graphOnly) parts.images = parts.scan = parts.grid = parts.userData = false;
  for (int id : ids) {
    if (optimized && graphOnly) break;  // neither odometry poses nor data needed
    std::optional<rtabmap::Signature> s = core_->node(id, parts);
    if (!s) continue;
    if (!optimized && !s->getPose().isNull()) poses.emplace(id, s->getPose());
    if (!graphOnly) nodes.emplace(id, std::move(*s));
  }
  std::multimap<int, rtabmap::Link> links;
  for (const auto& [from, link] : global ? core_->allLinks() : core_->localLinks()) {
    if (poses.count(link.from()) && poses.count(link.to())) links.emplace(from, link);
  }
  return rtabmap_conversions::mapDataToMsg(poses, links, nodes, core_->mapCorrection(), mapHeader(stamp));
}

bool RtabmapNodelet::onGetMapData(rtabmap_ros::GetMap::Request& req, rtabmap_ros::GetMap::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("get_map_data")) return false;
  res.data = mapDataOf(req.global, req.optimized, req.graphOnly, ros::Time::now());
  return true;
}

bool RtabmapNodelet::onPublishMap(rtabmap_ros::PublishMap::Request& req, rtabmap_ros::PublishMap::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("publish_map")) return false;
  const ros::Time now = ros::Time::now();
  mapDataPub_.publish(mapDataOf(req.global, req.optimized, req.graphOnly, now));
  publishMarkers(now, true);
  if (gridMapPub_.getNumSubscribers() > 0) publishGrid(now);
  publishMaps(now, true);
  return true;
}

bool RtabmapNodelet::onGetNodeData(rtabmap_ros::GetNodeData::Request& req, rtabmap_ros::GetNodeData::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("get_node_data")) return false;
  if (req.ids.empty()) {
    NODELET_WARN("%s: get_node_data: no node id asked.", getName().c_str());
    return false;
  }
  rtabmap::NodeDataParts parts;
  parts.images = req.images;
  parts.scan = req.scan;
  parts.grid = req.grid;
  parts.userData = req.user_data;
  for (int id : req.ids) {
    std::optional<rtabmap::Signature> s = core_->node(id, parts);
    if (!s) {
      NODELET_WARN("%s: get_node_data: node %d is not in the map.", getName().c_str(), id);
      res.data.clear();
      return false;
    }
    res.data.push_back(rtabmap_conversions::nodeDataToMsg(*s));
  }
  return true;
}

bool RtabmapNodelet::onGetNodesInRadius(rtabmap_ros::GetNodesInRadius::Request& req,
                                        rtabmap_ros::GetNodesInRadius::Response& res) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!haveCore("get_nodes_in_radius")) return false;
  const std::map<int, rtabmap::Transform> poses = core_->optimizedPoses();
  rtabmap::Transform center(req.x, req.y, req.z, 0, 0, 0);
  if (req.node_id != 0) {
    auto it = poses.find(req.node_id);
    if (it == poses.end()) {
      NODELET_WARN("%s: get_nodes_in_radius: node %d has no pose in the current map.", getName().c_str(), req.node_id);
      return false;
    }
    center = it->second;
  } else if (center.isInvalid()) {
    NODELET_WARN("%s: get_nodes_in_radius: the position is not finite.", getName().c_str());
    return false;
  }
  for (const auto& [id, pose] : rtabmap_slam_node::nodesInRadius(poses, center, req.radius, req.k)) {
    res.ids.push_back(id);
    res.poses.push_back(rtabmap_conversions::transformToPoseMsg(pose));
  }
  return true;
}

}  // namespace rtabmap_ros
