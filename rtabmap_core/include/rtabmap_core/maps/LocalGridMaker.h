#pragma once
// The local occupancy grid of a node (JFR 2019, 4.3.3): computed once, when the node is
// created, from its sensor data, and stored with it (SensorData::localGrid(), the database's
// ground/obstacle/empty cells). The global maps (OccupancyGrid, OctoMap, CloudMap) are then
// assembled from these local grids with the graph's poses, never from raw sensor data again.
//
//   LocalGridResult r = createLocalGrid(data, LocalGridOptions::fromParameters(parameters));
//   if (!r.success) RTABMAP_WARN("node " << data.id() << ": no local grid: " << r.why);
//   else data.setLocalGrid(r.grid);
//
// Which path runs (Grid/Sensor):
//  - scan (0): a 2D scan is ray traced in 2D; a 3D scan goes through the cloud path below;
//  - depth (1): the depth image, or a stereo pair turned into depth by block matching, becomes a
//    cloud, then voxel filter, height limits, footprint removal, ground / obstacle segmentation
//    (normals or height), obstacle clustering, noise filter, then a 2D projection (optionally ray
//    traced) or a 3D grid (optionally ray traced through OctoMap);
//  - both (2): the depth path, with the scan's points added as obstacles after segmentation
//    (a planar scan has no usable normals) and, for a 2D grid, its free space ray traced.
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/maps/LocalGridOptions.h"

namespace rtabmap {

// What createLocalGrid did, stage by stage (for statistics and for users who wonder why a grid
// is empty).
struct LocalGridStats {
  int inputPoints = 0;        // scan beams or depth pixels read
  int invalidPoints = 0;      // NaN / inf / zero depth
  int outOfRange = 0;         // outside Grid/RangeMin..RangeMax
  int cloudPoints = 0;        // cloud path: points after range filtering
  int voxelPoints = 0;        // after the voxel filter
  int heightCropped = 0;      // removed by Grid/MaxObstacleHeight
  int footprintRemoved = 0;   // removed as the robot's own body
  int groundPoints = 0;       // after segmentation
  int obstaclePoints = 0;
  int flatObstacleClusters = 0;  // flat surfaces above the floor classified obstacle
  int clustersKept = 0;
  int clustersDropped = 0;    // smaller than Grid/MinClusterSize
  int noiseRemoved = 0;
  int groundCells = 0;        // in the result
  int obstacleCells = 0;
  int emptyCells = 0;
  // Milliseconds per stage, keyed by stage name ("cloud", "voxel", "segmentation", ...).
  std::map<std::string, double> stageMs;
  double totalMs = 0.0;
};

struct LocalGridResult {
  // True when a grid with at least one cell was made. False: `grid` is empty and `why` says
  // what was wrong with the input (no data for Grid/Sensor, all ranges invalid, a depth image
  // without valid pixel, everything removed by the filters...). Never an empty grid that looks
  // valid.
  bool success = false;
  std::string why;
  // Input that was dropped but did not prevent the grid (e.g. "12 of 180 beams are NaN or inf").
  std::vector<std::string> warnings;
  // "scan 2D", "scan 3D", "depth", "stereo", "depth+scan", "stereo+scan".
  std::string source;
  LocalGrid grid;
  LocalGridStats stats;
};

// Never throws on bad sensor data (that is a result with success = false and its reason);
// throws ParameterError when the options are invalid (LocalGridOptions::IsValid).
LocalGridResult createLocalGrid(const SensorData& data, const LocalGridOptions& options);

// Bytes a local grid takes: raw (cells as floats) and as the database stores it (each cell
// matrix through codec::compressData).
struct LocalGridBytes {
  size_t raw = 0;
  size_t compressed = 0;
};
LocalGridBytes localGridBytes(const LocalGrid& grid);

}  // namespace rtabmap
