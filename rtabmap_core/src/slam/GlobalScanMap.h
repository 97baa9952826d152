#pragma once
// RGBD/ProximityGlobalScanMap (localization mode): the laser scans of every node of the saved
// map, Long-Term Memory included, assembled once in the map frame at the nodes' optimised poses
// and voxel filtered. Localization then matches a new scan with one ICP against the part of this
// map around where the robot is assumed (RGBD/LocalRadius), instead of against pieces of earlier
// trajectories that are in RAM (ProximityBySpace.h): the robot localises on walls seen from every
// pass at once, also where it never drove, and nothing has to come back from the database
// first. The graph does not change in localization mode, so the map is built once per loaded map.
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/slam/RtabmapOptions.h"
#include "ProximityBySpace.h"

namespace rtabmap {

namespace memory {
class Memory;
}
class LinkRegistration;

class GlobalScanMap {
 public:
  // voxelSize: one averaged point per voxel of this size (m), 0 = every point kept.
  explicit GlobalScanMap(float voxelSize);

  // Adds scans, each with the pose of its node in the map frame (the scans' own local transforms
  // apply). Parts in another format than the first part added are skipped and counted. Call with
  // batches of nodes: each batch is voxel filtered before it joins, so the map never holds all
  // the raw points of a large 3D map at once.
  void add(const std::vector<std::pair<LaserScan, Transform>>& parts);
  // The nodes of the map and their poses (the link of a localization goes to the nearest one).
  void setNodes(std::map<int, Transform> poses) { nodes_ = std::move(poses); }
  // Filters what was added once more (voxels spanning two batches) and indexes it by cell.
  void finish();

  bool empty() const { return points_.empty(); }
  int points() const { return points_.size(); }
  int skippedParts() const { return skipped_; }
  const std::map<int, Transform>& nodes() const { return nodes_; }

  // The points within `radius` (m, in the plane) of `center`, in `center`'s frame: the viewpoint
  // normals are estimated from is then where the robot is assumed, as for one of its own scans.
  LaserScan around(const Transform& center, float radius) const;

 private:
  uint64_t cellOf(float x, float y) const;

  float voxelSize_;
  float cellSize_;
  LaserScan points_;  // map frame, identity local transform; sorted by cell after finish()
  std::unordered_map<uint64_t, std::pair<int, int>> cells_;  // cell -> [first, last) in points_
  std::map<int, Transform> nodes_;
  int skipped_ = 0;
};

// Localization on the global scan map: ICP of the new node's scan against the map within
// RGBD/LocalRadius of `estimate` (the robot's assumed pose), from `estimate`, after the
// correlative search of RGBD/ProximityCorrelativeWindow when it is set and the scans are 2D.
// Accepted when ICP's acceptance (Icp/) passes, when RGBD/ProximityGlobalScanMapMinRatio of the
// scan's points found the map, and when the scan constrains every direction (structural
// complexity, as for merged scans), the result is a link from the new node to the map node
// nearest to the corrected pose, its covariance ICP's times RGBD/ProximityMergedScanCovFactor.
// Refused, with the reason, when no map node is within RGBD/LocalRadius of the estimate: the
// robot is assumed off the map.
ProximityResult localizeOnGlobalScanMap(memory::Memory& memory, int currentId, const Transform& estimate,
                                        const GlobalScanMap& map, const RtabmapOptions& options,
                                        const LinkRegistration& registration, bool covOffDiagIgnored);

}  // namespace rtabmap
