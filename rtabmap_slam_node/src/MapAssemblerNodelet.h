#pragma once
// map_assembler: the SLAM node's map topics rebuilt from its mapData, e.g. on another machine
// than the robot's (also the node `map_assembler`).
//
// Topics in: mapData (rtabmap_ros/MapData): the SLAM node's incremental messages (the graph
//   and the data of the node each update added) and the whole map publish_map sends. Every
//   node's local grid is kept (a node sent again with the same grid changes nothing; with
//   another grid, e.g. after a reset of the SLAM node, the new one replaces it); the poses are
//   the last message's graph.
// Topics out (latched, each computed only while it has a subscriber, from the whole map when
//   one appears, then incrementally, on a worker thread (MapsPublisher.h: a mapData message is
//   never held up by an assembly; messages arriving meanwhile coalesce); frame: the mapData
//   header's): grid_map
//   (nav_msgs/OccupancyGrid: the same assembly as the SLAM node's, core OccupancyGrid),
//   cloud_map, octomap_binary, octomap_full, octomap_occupied_space, octomap_obstacles,
//   octomap_ground, octomap_empty_space, occupied_cells_vis_array, octomap_grid (see
//   MapsPublisher.h).
// Parameters: Grid/* and GridGlobal/* core parameters as private Group/Name parameters (the
//   SLAM node's values, so the maps match); queue_size (10) of mapData.
// Services: reset (std_srvs/Empty): forget every grid and map.
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <rtabmap_ros/MapData.h>
#include <std_msgs/Header.h>
#include <std_srvs/Empty.h>

#include <map>
#include <mutex>

#include "MapsPublisher.h"
#include "rtabmap_slam_node/MapsAssembler.h"

namespace rtabmap_ros {

class MapAssemblerNodelet : public nodelet::Nodelet {
 private:
  void onInit() override;
  void onMapData(const rtabmap_ros::MapDataConstPtr& msg);
  void onMapSubscriber();
  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  void publish(const std_msgs::Header& header, bool force = false);

  std::mutex mutex_;  // mapData vs new subscribers and services
  rtabmap_slam_node::LocalGridStore grids_;
  std::map<int, rtabmap::Transform> poses_;  // of the last mapData
  std_msgs::Header header_;                  // of the last mapData
  bool received_ = false;
  MapsPublisher maps_;
  ros::Subscriber mapDataSub_;
  ros::ServiceServer resetSrv_;
};

}  // namespace rtabmap_ros
