#pragma once
// The checks a global map (2D grid, OctoMap) applies to a node's local grid before adding it.
#include <cmath>
#include <string>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/maps/Cloud.h"

namespace rtabmap::maps_detail {

// Why the local grid cannot go into a map of this cell size ("" when it can). mapName names the
// map in the message ("the map", "the OctoMap").
inline std::string localGridProblem(const LocalGrid& grid, float cellSize, const std::string& mapName) {
  if (grid.isEmpty()) return "its local grid is empty (nothing to add)";
  if (std::abs(grid.cellSize - cellSize) > 1e-6f * cellSize) {
    return "its local grid has cells of " + std::to_string(grid.cellSize) + " m but " + mapName +
           " uses Grid/CellSize " + std::to_string(cellSize) + " m";
  }
  for (const cv::Mat* m : {&grid.ground, &grid.obstacles, &grid.empty}) {
    if (!isCellMatrix(*m)) return "its local grid cells are not CV_32FC2/3/4 1xN matrices";
  }
  return "";
}

}  // namespace rtabmap::maps_detail
