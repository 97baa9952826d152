#pragma once
// The 3D maps as messages (unit-tested without a master): clouds as sensor_msgs/PointCloud2,
// the octree as rtabmap_ros/OctoMap (octomap_msgs/Octomap's fields: octomap_msgs is not
// packaged here), and the occupied voxels as a MarkerArray of cubes so stock rviz shows the
// octomap without its plugin.
#include <rtabmap_ros/OctoMap.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/maps/OctoMap.h"

namespace rtabmap_slam_node {

// Unorganised (height 1), packed little-endian float32 fields x y z, and rgb (the colour
// packed as 0x00RRGGBB in the float's bits, as PCL and rviz's RGB8 transformer read it) when
// the cloud has colours.
sensor_msgs::PointCloud2 cloudToMsg(const rtabmap::Cloud& cloud, const std_msgs::Header& header);

rtabmap_ros::OctoMap octoMapToMsg(const rtabmap::OctoMapMessage& octomap, const std_msgs::Header& header);

// The occupied voxels (obstacles then ground), as octomap_occupied_space publishes them.
rtabmap::Cloud occupiedVoxels(const rtabmap::OctoMapCells& cells);

// After a DELETEALL, one CUBE_LIST of voxelSize cubes per kind, so rviz can toggle them:
// namespace "obstacles" and "ground". Each cube has its voxel's colour when the map has colour,
// else a colour of its height (blue low to red high over the map's height range, as
// octomap_server's occupied_cells_vis_array does). Kinds without voxels have no marker.
visualization_msgs::MarkerArray occupiedCellsMarkers(const rtabmap::OctoMapCells& cells,
                                                     const std_msgs::Header& header);

}  // namespace rtabmap_slam_node
