#pragma once
// The global 3D map: a colour OcTree (liboctomap's ColorOcTree) fed from the nodes' 3D local
// grids with the graph's poses (JFR 2019, 4.3.6). Each node inserts its obstacle and ground
// voxels as occupied (the floor is a surface), remembering which occupied voxels are ground, and
// its free space: the empty voxels of its local grid, or, when it has none and ray tracing is on
// (Grid/RayTracing), the voxels crossed by rays from its view point to each of its voxels (each
// voxel updated once per node; occupied wins over free). An octree cannot move what it holds,
// so when optimisation moves a node by more than GridGlobal/UpdateError the tree is rebuilt from
// the cached local grids.
//
// Resolution = Grid/CellSize; queries and exports can be made coarser with a tree depth (16 is
// the full resolution, e.g. 5 cm; each level less doubles the voxel size).
//
// Nothing of liboctomap appears here: the ROS layer gets the octomap_msgs/Octomap fields through
// toMessage(), and files through writeBinary() (.bt) / write() (.ot).
#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/maps/GridMap.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

struct OctoMapOptions {
  float cellSize = 0.05f;          // Grid/CellSize: leaf voxel size
  int treeDepth = 16;              // GridGlobal/OctoMapTreeDepth: default depth of queries
  float probHit = 0.7f;            // GridGlobal/ProbHit
  float probMiss = 0.4f;           // GridGlobal/ProbMiss
  float probClampingMin = 0.1192f; // GridGlobal/ProbClampingMin
  float probClampingMax = 0.971f;  // GridGlobal/ProbClampingMax
  float occupancyThr = 0.5f;       // GridGlobal/OccupancyThr
  bool rayTracing = false;         // Grid/RayTracing: cast rays for nodes without empty voxels
  float rangeMax = 0.0f;           // Grid/RangeMax: longest ray (0 = none)
  float updateError = 0.01f;       // GridGlobal/UpdateError (m)
  int floodFillDepth = 0;          // GridGlobal/FloodFillDepth: 0 = off

  static OctoMapOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
  void validate() const;  // throws ParameterError
};

struct OctoMapUpdateSummary {
  bool rebuilt = false;       // the tree was cleared and every node inserted again
  std::string why;            // what changed
  int nodesInserted = 0;
  int nodesMoved = 0;
  int nodesRemoved = 0;
  int nodesWithoutGrid = 0;
  long pointsInserted = 0;    // ground + obstacle voxels of the inserted nodes
  long freeVoxelUpdates = 0;  // free updates (empty voxels and ray-traced ones)
  long rayTracedPoints = 0;   // points whose ray was cast here
  double timeMs = 0.0;
};

// What a voxel is, for queries.
enum class VoxelState : uint8_t { kUnknown = 0, kFree = 1, kGround = 2, kObstacle = 3 };

// Voxel centres by kind, at some tree depth (see OctoMap::cells).
struct OctoMapCells {
  Cloud obstacles;  // occupied, not ground (coloured when the map has colour)
  Cloud ground;     // occupied ground
  Cloud empty;      // free
  Cloud frontiers;  // free voxels with an unknown face neighbour (where exploration goes)
  float voxelSize = 0.0f;
};

// The octomap_msgs/Octomap fields (rtabmap_ros/OctoMap message).
struct OctoMapMessage {
  bool binary = true;       // true: occupancy only, 2 bits per node ("OcTree")
  std::string id;           // tree type: "OcTree" (binary) or "ColorOcTree" (full)
  double resolution = 0.0;
  std::vector<int8_t> data;
};

class OctoMap {
 public:
  explicit OctoMap(const OctoMapOptions& options = OctoMapOptions());  // ParameterError
  ~OctoMap();
  OctoMap(OctoMap&&) noexcept;
  OctoMap& operator=(OctoMap&&) noexcept;

  const OctoMapOptions& options() const;

  // Same contract as OccupancyGrid::addLocalGrid (2D grids are accepted, at z = 0).
  bool addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why = nullptr);
  bool hasLocalGrid(int nodeId) const;
  void removeLocalGrid(int nodeId);
  size_t cachedNodes() const;

  // Inserts new nodes; rebuilds when a node moved or was removed.
  OctoMapUpdateSummary update(const std::map<int, Transform>& poses);

  // State of the voxel holding p at the given depth (0 = options.treeDepth).
  VoxelState state(const Eigen::Vector3f& p, int depth = 0) const;
  // All voxels by kind at the given depth (0 = options.treeDepth). Frontier search looks at the
  // 6 face neighbours of each free voxel.
  OctoMapCells cells(int depth = 0, bool withFrontiers = true) const;
  // 2D projection: occupied cells where an obstacle voxel lies between minZ and maxZ (both 0 =
  // any height), free cells where only ground voxels lie. Same map format as OccupancyGrid, at
  // the voxel size of the depth.
  GridMap projection2D(float minZ = 0.0f, float maxZ = 0.0f, int depth = 0) const;

  // Files: .bt (occupancy only, readable as a plain OcTree) and .ot (ColorOcTree with colours).
  // Return false (and log) when the file cannot be written or the map is empty.
  bool writeBinary(const std::string& path) const;
  bool write(const std::string& path) const;
  // The message fields: binary (occupancy, "OcTree") or full (ColorOcTree with colours).
  OctoMapMessage toMessage(bool binary = true) const;

  size_t leafCount() const;
  size_t memoryUsed() const;  // bytes of the tree, its ground set and the cached grids
  bool hasColor() const;
  bool empty() const;
  void clear();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap
