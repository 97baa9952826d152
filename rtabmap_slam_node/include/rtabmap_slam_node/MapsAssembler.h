#pragma once
// The global maps a listener asked for, assembled from the nodes' local grids and the graph's
// poses: the point cloud (core CloudMap: cloud_map), the OctoMap (core OctoMap: octomap_*) and
// the 2D occupancy grid (core OccupancyGrid: map_assembler's grid_map). One copy for the SLAM
// nodelet (grids read from the core) and map_assembler (grids kept from mapData); ROS-free.
//
// Lazy on purpose: maintaining a cloud or an octree costs memory and time at every update, so a
// map exists only while it is wanted. The first update that wants it creates it and assembles
// every node of the graph (its grid asked once from the source); the next ones only bring it to
// the new poses through the core's incremental update (new nodes added, moved ones re-placed or
// the octree rebuilt, see CloudMap.h / OctoMap.h / OccupancyGrid.h). An update that no longer
// wants a map drops it. Nothing wanted: update() returns at once, nothing fetched or computed.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/CloudMap.h"
#include "rtabmap_core/maps/OccupancyGrid.h"
#include "rtabmap_core/maps/OctoMap.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap_slam_node {

// Which maps someone listens to.
struct MapsWanted {
  bool cloud = false;    // CloudMap
  bool octomap = false;  // OctoMap
  bool grid = false;     // OccupancyGrid
  bool any() const { return cloud || octomap || grid; }
};

// What one update() did (all zero when nothing was wanted).
struct MapsUpdateSummary {
  int gridsFetched = 0;      // local grids asked to the source
  int graphNodes = 0;        // nodes of `poses` with a usable pose (what a complete map assembles)
  int cloudNodes = 0;        // nodes assembled in each map after the update (0 = no such map)
  int octomapNodes = 0;
  int gridNodes = 0;
  bool octomapRebuilt = false;
  // The map was created, or nodes were added, moved or removed: its messages are out of date.
  bool cloudChanged = false;
  bool octomapChanged = false;
  bool gridChanged = false;
  double timeMs = 0.0;       // fetching + assembling
  std::vector<std::string> refused;  // local grids a map could not use (each said once)
};

class MapsAssembler {
 public:
  // A node's local grid (nullopt or an empty grid: the node has none).
  using GridSource = std::function<std::optional<rtabmap::LocalGrid>(int nodeId)>;

  // Grid/* and GridGlobal/* of `parameters` (defaults for the others). Throws ParameterError
  // when they are invalid, so a bad value shows at start, not at the first subscriber.
  explicit MapsAssembler(const rtabmap::ParametersMap& parameters = rtabmap::ParametersMap());

  // Brings the wanted maps to `poses` (node id -> pose in the map frame; null poses ignored),
  // asking `source` for the grids of nodes a map does not have yet.
  MapsUpdateSummary update(const std::map<int, rtabmap::Transform>& poses, const MapsWanted& wanted,
                           const GridSource& source);
  // The node's local grid changed (e.g. a node id reused after a reset): asked again.
  void invalidate(int nodeId);
  // Drops every map (a new map, another database).
  void clear();

  // Null while not wanted.
  const rtabmap::CloudMap* cloudMap() const { return cloud_.get(); }
  const rtabmap::OctoMap* octoMap() const { return octomap_.get(); }
  const rtabmap::OccupancyGrid* occupancyGrid() const { return grid_.get(); }
  // GridGlobal/OctoMapTreeDepth: the depth the octomap topics are published at.
  int octomapTreeDepth() const { return octomapOptions_.treeDepth; }
  // update() calls that wanted something: stays 0 as long as nobody listened.
  long assemblingUpdates() const { return assemblingUpdates_; }

 private:
  rtabmap::CloudMapOptions cloudOptions_;
  rtabmap::OctoMapOptions octomapOptions_;
  rtabmap::GlobalGridOptions gridOptions_;
  std::unique_ptr<rtabmap::CloudMap> cloud_;
  std::unique_ptr<rtabmap::OctoMap> octomap_;
  std::unique_ptr<rtabmap::OccupancyGrid> grid_;
  std::set<int> withoutGrid_;                 // the source had no grid: not asked again
  std::map<std::string, std::set<int>> refused_;  // per map: grids it refused (not offered again)
  long assemblingUpdates_ = 0;
};

// map_assembler's copy of the nodes' local grids: mapData brings each node's data once (and
// again after publish_map, or another map after a reset of the SLAM node reusing ids).
class LocalGridStore {
 public:
  // Keeps the grid (an empty one is ignored: the graph view of a node carries none). True when
  // it is new or differs from the one kept: the maps must take it again (invalidate()).
  bool add(int nodeId, const rtabmap::LocalGrid& grid);
  std::optional<rtabmap::LocalGrid> get(int nodeId) const;
  size_t size() const { return grids_.size(); }
  void clear() { grids_.clear(); }

 private:
  std::map<int, rtabmap::LocalGrid> grids_;
};

// Same cells (types, sizes and bytes), cell size and view point.
bool sameLocalGrid(const rtabmap::LocalGrid& a, const rtabmap::LocalGrid& b);

}  // namespace rtabmap_slam_node
