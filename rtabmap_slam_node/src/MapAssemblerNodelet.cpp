// map_assembler (MapAssemblerNodelet.h).
#include "MapAssemblerNodelet.h"

#include <pluginlib/class_list_macros.hpp>

#include "rtabmap_conversions/CoreLog.h"
#include "rtabmap_conversions/NodeDataConversions.h"
#include "rtabmap_odom/NodeParameters.h"
#include "rtabmap_odom/PrivateParameters.h"

namespace rtabmap_ros {

void MapAssemblerNodelet::onInit() {
  rtabmap_conversions::routeCoreLogToRosconsole();
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  const std::map<std::string, std::string> raw = rtabmap_odom::privateParameters(pnh);
  rtabmap_odom::CoreParameters core = rtabmap_odom::coreParametersFromPrivate(raw);
  std::vector<std::string> warnings = rtabmap_odom::unknownNodeParameters(raw, {"queue_size"});
  warnings.insert(warnings.end(), core.warnings.begin(), core.warnings.end());
  for (const std::string& w : warnings) NODELET_WARN("%s: %s", getName().c_str(), w.c_str());
  for (const auto& [key, value] : core.parameters) NODELET_INFO("%s: %s = %s", getName().c_str(), key.c_str(), value.c_str());
  try {
    maps_.setParameters(core.parameters);
  } catch (const std::exception& e) {
    NODELET_ERROR("%s: %s; using the defaults.", getName().c_str(), e.what());
  }
  int queueSize = 10;
  pnh.param("queue_size", queueSize, queueSize);
  maps_.advertise(nh, true, [this] { onMapSubscriber(); });
  resetSrv_ = nh.advertiseService("reset", &MapAssemblerNodelet::onReset, this);
  mapDataSub_ = nh.subscribe("mapData", std::max(1, queueSize), &MapAssemblerNodelet::onMapData, this);
  NODELET_INFO("%s: assembling maps from %s", getName().c_str(), mapDataSub_.getTopic().c_str());
}

void MapAssemblerNodelet::onMapData(const rtabmap_ros::MapDataConstPtr& msg) {
  std::string error;
  std::optional<rtabmap_conversions::MapData> data = rtabmap_conversions::mapDataFromMsg(*msg, &error);
  if (!data) {
    NODELET_WARN("%s: mapData at %.6f ignored: %s", getName().c_str(), msg->header.stamp.toSec(), error.c_str());
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, node] : data->nodes) {
    if (grids_.add(id, node.sensorData().localGrid())) maps_.invalidate(id);
  }
  poses_ = std::move(data->graph.poses);
  header_ = msg->header;
  received_ = true;
  publish(header_);
}

void MapAssemblerNodelet::publish(const std_msgs::Header& header, bool force) {
  // The maps worker assembles and publishes on its own thread: mapData is never held up.
  maps_.submit(poses_, [this](int id) { return grids_.get(id); }, header, force);
  const rtabmap_slam_node::MapsWorkerStats w = maps_.workerStats();
  NODELET_DEBUG("%s: %zu nodes, %zu grids kept; last assembly: %d grids taken, cloud %d nodes, octomap %d nodes, "
                "grid %d nodes, %.1f ms; %ld jobs coalesced", getName().c_str(), poses_.size(), grids_.size(),
                w.last.gridsFetched, w.last.cloudNodes, w.last.octomapNodes, w.last.gridNodes, w.last.timeMs,
                w.coalescedJobs);
}

void MapAssemblerNodelet::onMapSubscriber() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!received_) return;  // nothing to say before the first mapData
  std_msgs::Header header = header_;
  header.stamp = ros::Time::now();
  publish(header, true);
}

bool MapAssemblerNodelet::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  std::lock_guard<std::mutex> lock(mutex_);
  grids_.clear();
  poses_.clear();
  maps_.clear();
  received_ = false;
  NODELET_INFO("%s: reset: every grid and map forgotten.", getName().c_str());
  return true;
}

}  // namespace rtabmap_ros

PLUGINLIB_EXPORT_CLASS(rtabmap_ros::MapAssemblerNodelet, nodelet::Nodelet)
