// The 3D map topics (MapsPublisher.h).
#include "MapsPublisher.h"

#include <nav_msgs/OccupancyGrid.h>
#include <rtabmap_ros/OctoMap.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <chrono>

#include "rtabmap_slam_node/MapsMessages.h"
#include "rtabmap_slam_node/SlamNodeSupport.h"

namespace rtabmap_ros {

namespace {

template <class M>
ros::Publisher latched(ros::NodeHandle& nh, const std::string& topic, const ros::SubscriberStatusCallback& onConnect) {
  return nh.advertise<M>(topic, 1, onConnect, ros::SubscriberStatusCallback(), ros::VoidConstPtr(), true);
}

bool listened(const ros::Publisher& p) { return p && p.getNumSubscribers() > 0; }

}  // namespace

void MapsPublisher::advertise(ros::NodeHandle& nh, bool withGrid, const std::function<void()>& onSubscriber) {
  withGrid_ = withGrid;
  const ros::SubscriberStatusCallback onConnect = [onSubscriber](const ros::SingleSubscriberPublisher&) {
    if (onSubscriber) onSubscriber();
  };
  cloudPub_ = latched<sensor_msgs::PointCloud2>(nh, "cloud_map", onConnect);
  octomapBinaryPub_ = latched<rtabmap_ros::OctoMap>(nh, "octomap_binary", onConnect);
  octomapFullPub_ = latched<rtabmap_ros::OctoMap>(nh, "octomap_full", onConnect);
  occupiedPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_occupied_space", onConnect);
  obstaclesPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_obstacles", onConnect);
  groundPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_ground", onConnect);
  emptyPub_ = latched<sensor_msgs::PointCloud2>(nh, "octomap_empty_space", onConnect);
  occupiedMarkersPub_ = latched<visualization_msgs::MarkerArray>(nh, "occupied_cells_vis_array", onConnect);
  octomapGridPub_ = latched<nav_msgs::OccupancyGrid>(nh, "octomap_grid", onConnect);
  if (withGrid_) gridPub_ = latched<nav_msgs::OccupancyGrid>(nh, "grid_map", onConnect);
}

void MapsPublisher::setParameters(const rtabmap::ParametersMap& parameters) {
  rtabmap_slam_node::MapsAssembler fresh(parameters);  // throws before anything changes
  earlierAssemblingUpdates_ += assembler_.assemblingUpdates();
  assembler_ = std::move(fresh);
}

void MapsPublisher::clear() { assembler_.clear(); }

bool MapsPublisher::octomapCellsWanted() const {
  return listened(occupiedPub_) || listened(obstaclesPub_) || listened(groundPub_) || listened(emptyPub_) ||
         listened(occupiedMarkersPub_);
}

rtabmap_slam_node::MapsWanted MapsPublisher::wanted() const {
  rtabmap_slam_node::MapsWanted w;
  w.cloud = listened(cloudPub_);
  w.octomap = listened(octomapBinaryPub_) || listened(octomapFullPub_) || listened(octomapGridPub_) ||
              octomapCellsWanted();
  w.grid = withGrid_ && listened(gridPub_);
  return w;
}

rtabmap_slam_node::MapsUpdateSummary MapsPublisher::publish(
    const std::map<int, rtabmap::Transform>& poses, const rtabmap_slam_node::MapsAssembler::GridSource& source,
    const std_msgs::Header& header, bool force) {
  const auto start = std::chrono::steady_clock::now();
  const rtabmap_slam_node::MapsWanted w = wanted();
  rtabmap_slam_node::MapsUpdateSummary summary = assembler_.update(poses, w, source);
  for (const std::string& why : summary.refused) ROS_WARN("maps: %s; the node is left out of that map.", why.c_str());

  // An unchanged map's latched message is still right: not made again.
  const rtabmap::CloudMap* cloud = force || summary.cloudChanged ? assembler_.cloudMap() : nullptr;
  const rtabmap::OctoMap* octomap = force || summary.octomapChanged ? assembler_.octoMap() : nullptr;
  const rtabmap::OccupancyGrid* grid = force || summary.gridChanged ? assembler_.occupancyGrid() : nullptr;
  if (cloud) {
    cloudPub_.publish(rtabmap_slam_node::cloudToMsg(cloud->cloud(), header));
  }
  if (octomap) {
    if (listened(octomapBinaryPub_)) {
      octomapBinaryPub_.publish(rtabmap_slam_node::octoMapToMsg(octomap->toMessage(true), header));
    }
    if (listened(octomapFullPub_)) {
      octomapFullPub_.publish(rtabmap_slam_node::octoMapToMsg(octomap->toMessage(false), header));
    }
    const int depth = assembler_.octomapTreeDepth();
    if (listened(octomapGridPub_)) {
      const rtabmap::GridMap projected = octomap->projection2D(0.0f, 0.0f, depth);
      if (!projected.empty()) octomapGridPub_.publish(rtabmap_slam_node::gridMapToMsg(projected, header));
    }
    if (octomapCellsWanted()) {
      const rtabmap::OctoMapCells cells = octomap->cells(depth, false);
      if (listened(occupiedPub_)) {
        occupiedPub_.publish(rtabmap_slam_node::cloudToMsg(rtabmap_slam_node::occupiedVoxels(cells), header));
      }
      if (listened(obstaclesPub_)) obstaclesPub_.publish(rtabmap_slam_node::cloudToMsg(cells.obstacles, header));
      if (listened(groundPub_)) groundPub_.publish(rtabmap_slam_node::cloudToMsg(cells.ground, header));
      if (listened(emptyPub_)) emptyPub_.publish(rtabmap_slam_node::cloudToMsg(cells.empty, header));
      if (listened(occupiedMarkersPub_)) {
        occupiedMarkersPub_.publish(rtabmap_slam_node::occupiedCellsMarkers(cells, header));
      }
    }
  }
  if (grid) {
    const rtabmap::GridMap map = grid->map();
    if (!map.empty()) gridPub_.publish(rtabmap_slam_node::gridMapToMsg(map, header));
  }
  if (w.any()) {  // else nothing was done: 0, not the cost of asking the publishers
    summary.timeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return summary;
}

void MapsPublisher::addStatistics(const rtabmap_slam_node::MapsUpdateSummary& summary, rtabmap_ros::Info& info) const {
  const std::pair<const char*, double> entries[] = {
      {"Maps/Assembling_updates/", static_cast<double>(earlierAssemblingUpdates_ + assembler_.assemblingUpdates())},
      {"Maps/Grids_fetched/", summary.gridsFetched},
      {"Maps/Cloud_nodes/", summary.cloudNodes},
      {"Maps/OctoMap_nodes/", summary.octomapNodes},
      {"Maps/OctoMap_rebuilt/", summary.octomapRebuilt ? 1.0 : 0.0},
      {"Maps/Time/ms", summary.timeMs}};  // assembling and making the messages
  for (const auto& [key, value] : entries) {
    info.statsKeys.push_back(key);
    info.statsValues.push_back(static_cast<float>(value));
  }
}

}  // namespace rtabmap_ros
