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
//
// Off the owner's thread: submit() only takes what the maps lack (MapsHandover.h, cheap, under
// the owner's lock) and hands it to a worker thread that assembles and publishes
// (MapsWorker.h); a busy worker makes jobs coalesce, never a queue, never a wait.
#include <ros/ros.h>
#include <rtabmap_ros/Info.h>
#include <std_msgs/Header.h>

#include <functional>
#include <map>
#include <memory>

#include "rtabmap_slam_node/MapsAssembler.h"
#include "rtabmap_slam_node/MapsHandover.h"
#include "rtabmap_slam_node/MapsWorker.h"

namespace rtabmap_ros {

class MapsPublisher : private rtabmap_slam_node::MapsSink {
 public:
  MapsPublisher();
  ~MapsPublisher() override;  // stop()

  // withGrid: also grid_map, assembled here (map_assembler; the SLAM nodelet publishes the
  // core's). onSubscriber runs on the node's callback queue when a map topic gains a subscriber.
  void advertise(ros::NodeHandle& nh, bool withGrid, const std::function<void()>& onSubscriber);
  // Grid/* and GridGlobal/*; drops the maps. Throws ParameterError for invalid values.
  void setParameters(const rtabmap::ParametersMap& parameters);
  // Hands the worker `poses` and the grids it lacks (from `source`) for the maps someone listens
  // to; it publishes those that changed, or all of them when `force` (a new subscriber). Returns
  // at once. header: map frame. Call it under the lock that guards `source`'s data.
  void submit(const std::map<int, rtabmap::Transform>& poses,
              const rtabmap_slam_node::MapsAssembler::GridSource& source, const std_msgs::Header& header,
              bool force = false);
  // Another map: what is held is dropped, and nothing assembled before is published after this.
  void clear();
  void invalidate(int nodeId) { handover_.invalidate(nodeId); }
  // Joins the worker (the owner's destructor, before what the sources read goes away).
  void stop() { worker_.stop(); }

  // `info`'s Maps/...: the last COMPLETED assembly (an update's own job is usually still under
  // way when its info is published), see the .cpp.
  void addStatistics(rtabmap_ros::Info& info) const;
  rtabmap_slam_node::MapsWorkerStats workerStats() const { return worker_.stats(); }

 private:
  std::function<void()> prepare(const rtabmap_slam_node::MapsAssembler& maps,
                                const rtabmap_slam_node::MapsUpdateSummary& summary,
                                const rtabmap_slam_node::MapsJob& job) override;
  rtabmap_slam_node::MapsWanted wanted() const;
  bool octomapCellsWanted() const;

  bool withGrid_ = false;
  ros::Publisher cloudPub_, gridPub_;
  ros::Publisher octomapBinaryPub_, octomapFullPub_, octomapGridPub_;
  ros::Publisher occupiedPub_, obstaclesPub_, groundPub_, emptyPub_, occupiedMarkersPub_;
  rtabmap_slam_node::MapsHandover handover_;  // the owner's thread, under its lock
  rtabmap_slam_node::MapsWorker worker_;      // last: its thread uses the publishers
};

}  // namespace rtabmap_ros
