#pragma once
// Local grids shared by the map tests of this folder (MapsAssembler, MapsWorker).
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/maps/Cloud.h"

namespace rtabmap_slam_node::test {

// A node's local grid in its base frame (cells of 5 cm; cellSize is only what the grid says):
// a wall of obstacle cells 1 m ahead (x = 1.025, y and z from 0 to 0.4) and a floor of ground
// cells (z = 0) between the robot and the wall.
inline rtabmap::LocalGrid wallAhead(float cellSize = 0.05f) {
  rtabmap::Cloud obstacles, ground;
  for (int j = 0; j < 8; ++j) {
    const float y = 0.025f + 0.05f * j;
    for (int k = 0; k < 8; ++k) obstacles.push_back(cv::Point3f(1.025f, y, 0.025f + 0.05f * k));
    for (int i = 0; i < 20; ++i) ground.push_back(cv::Point3f(0.025f + 0.05f * i, y, 0.0f));
  }
  rtabmap::LocalGrid g;
  g.obstacles = rtabmap::cellsFromCloud(obstacles, false);
  g.ground = rtabmap::cellsFromCloud(ground, false);
  g.cellSize = cellSize;
  return g;
}

}  // namespace rtabmap_slam_node::test
