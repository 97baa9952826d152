#pragma once
// The assembled point-cloud map: each node's obstacle and ground cells (coloured when the node
// had an RGB image) in the map frame, voxel filtered at Grid/CellSize. Moving a node after
// optimisation only re-transforms that node's points: the cloud is a union, so "only what moved"
// is exact and always cheapest.
#include <map>
#include <memory>
#include <string>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

struct CloudMapOptions {
  float voxelSize = 0.05f;     // Grid/CellSize (0 = no voxel filter)
  bool ground = true;          // include ground cells
  bool obstacles = true;       // include obstacle cells
  float updateError = 0.01f;   // GridGlobal/UpdateError (m)

  static CloudMapOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct CloudMapUpdateSummary {
  int nodesAdded = 0;
  int nodesMoved = 0;
  int nodesRemoved = 0;
  int nodesWithoutGrid = 0;
  double timeMs = 0.0;
};

class CloudMap {
 public:
  explicit CloudMap(const CloudMapOptions& options = CloudMapOptions());  // ParameterError
  ~CloudMap();
  CloudMap(CloudMap&&) noexcept;
  CloudMap& operator=(CloudMap&&) noexcept;

  bool addLocalGrid(int nodeId, const LocalGrid& grid, std::string* why = nullptr);
  bool hasLocalGrid(int nodeId) const;
  void removeLocalGrid(int nodeId);
  CloudMapUpdateSummary update(const std::map<int, Transform>& poses);
  // The voxel-filtered union (computed on demand, cached until the next change).
  const Cloud& cloud() const;
  // Points before the voxel filter.
  size_t rawPoints() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap
