#pragma once
// The 3D map topics of the SLAM nodelet and of map_assembler (one copy): cloud_map
// (sensor_msgs/PointCloud2: obstacle and ground cells of every node, coloured when the nodes
// had RGB), octomap_binary / octomap_full (rtabmap_ros/OctoMap), octomap_occupied_space,
// octomap_obstacles, octomap_ground, octomap_empty_space (PointCloud2 of voxel centres at
// GridGlobal/OctoMapTreeDepth), occupied_cells_vis_array (visualization_msgs/MarkerArray of
// cubes, octomap_server's name, for stock rviz), octomap_grid (nav_msgs/OccupancyGrid: the
// octomap projected on the floor), and for map_assembler grid_map (nav_msgs/OccupancyGrid).
// All latched, and computed only for the topics someone subscribes to: a map that nobody
// listens to is not maintained (rtabmap_slam_node/MapsAssembler.h); a new subscriber makes the
// owner publish at once (the onSubscriber callback), built from the whole current map. After
// that a map's topics are published again only when an update changed it.
#include <ros/ros.h>
#include <rtabmap_ros/Info.h>
#include <std_msgs/Header.h>

#include <functional>
#include <map>
#include <memory>

#include "rtabmap_slam_node/MapsAssembler.h"

namespace rtabmap_ros {

class MapsPublisher {
 public:
  // withGrid: also grid_map, assembled here (map_assembler; the SLAM nodelet publishes the
  // core's). onSubscriber runs on the node's callback queue when a map topic gains a subscriber.
  void advertise(ros::NodeHandle& nh, bool withGrid, const std::function<void()>& onSubscriber);
  // Grid/* and GridGlobal/*; drops the maps. Throws ParameterError for invalid values.
  void setParameters(const rtabmap::ParametersMap& parameters);
  // Brings the maps someone listens to up to `poses` and publishes those that changed, or all
  // of them when `force` (a new subscriber). header: map frame.
  rtabmap_slam_node::MapsUpdateSummary publish(const std::map<int, rtabmap::Transform>& poses,
                                               const rtabmap_slam_node::MapsAssembler::GridSource& source,
                                               const std_msgs::Header& header, bool force = false);
  void clear();  // another map: what is held is dropped
  void invalidate(int nodeId) { assembler_.invalidate(nodeId); }

  // The last publish() in `info` (Maps/...: see the .cpp); Maps/Assembling_updates/ counts
  // the updates that assembled anything since start, 0 as long as nobody listened.
  void addStatistics(const rtabmap_slam_node::MapsUpdateSummary& summary, rtabmap_ros::Info& info) const;

 private:
  rtabmap_slam_node::MapsWanted wanted() const;
  bool octomapCellsWanted() const;

  rtabmap_slam_node::MapsAssembler assembler_;
  long earlierAssemblingUpdates_ = 0;  // of the assemblers before the last setParameters()
  bool withGrid_ = false;
  ros::Publisher cloudPub_, gridPub_;
  ros::Publisher octomapBinaryPub_, octomapFullPub_, octomapGridPub_;
  ros::Publisher occupiedPub_, obstaclesPub_, groundPub_, emptyPub_, occupiedMarkersPub_;
};

}  // namespace rtabmap_ros
