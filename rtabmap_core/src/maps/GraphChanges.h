#pragma once
// What changed in the graph since a global map was last assembled: shared by the 2D grid, the
// OctoMap and the cloud map. Internal to the maps area.
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::maps_detail {

struct GraphChanges {
  std::vector<int> added;        // to assemble, not assembled yet (increasing ids)
  std::vector<int> moved;        // assembled, and moved beyond the update error (or grid replaced)
  std::vector<int> removed;      // assembled, no longer selected
  int withoutGrid = 0;           // poses given for nodes without a cached local grid
  int selected = 0;              // nodes with a grid and a usable pose
  // The map after the update: node -> pose it is assembled at (unmoved nodes keep theirs).
  std::map<int, Transform> target;

  bool graphChanged() const { return !moved.empty() || !removed.empty(); }
  std::string describe() const {
    std::ostringstream s;
    s << added.size() << " new, " << moved.size() << " moved, " << removed.size() << " removed";
    return s.str();
  }
};

// Largest displacement of a node's cells between two poses: translation plus rotation angle times
// the distance of its farthest cell (a small yaw change moves far cells of a long-range scan).
inline double cellDisplacement(const Transform& a, const Transform& b, float radius) {
  const Transform delta = a.inverse() * b;
  return (a.translation() - b.translation()).norm() + delta.getAngle() * radius;
}

// hasGrid(id), radius(id): the cache. forcedMoved: nodes whose grid was replaced.
// maxNodes > 0 keeps the newest (largest ids); altitudeDelta > 0 keeps nodes within that height
// of the newest node.
inline GraphChanges diffGraph(const std::map<int, Transform>& poses,
                              const std::map<int, Transform>& assembled,
                              const std::function<bool(int)>& hasGrid,
                              const std::function<float(int)>& radius, float updateError,
                              const std::set<int>& forcedMoved, int maxNodes = 0,
                              float altitudeDelta = 0.0f) {
  GraphChanges c;
  std::map<int, Transform> selection;
  for (const auto& [id, pose] : poses) {
    if (pose.isNull() || pose.isInvalid()) continue;
    if (!hasGrid(id)) {
      ++c.withoutGrid;
      continue;
    }
    selection.emplace(id, pose);
  }
  if (altitudeDelta > 0.0f && !selection.empty()) {
    const double z = selection.rbegin()->second.z();
    for (auto it = selection.begin(); it != selection.end();) {
      it = std::abs(it->second.z() - z) > altitudeDelta ? selection.erase(it) : std::next(it);
    }
  }
  if (maxNodes > 0) {
    while (static_cast<int>(selection.size()) > maxNodes) selection.erase(selection.begin());
  }
  c.selected = static_cast<int>(selection.size());
  for (const auto& [id, pose] : assembled) {
    if (!selection.count(id)) c.removed.push_back(id);
  }
  for (const auto& [id, pose] : selection) {
    auto it = assembled.find(id);
    if (it == assembled.end()) {
      c.added.push_back(id);
      c.target.emplace(id, pose);
    } else if (forcedMoved.count(id) || cellDisplacement(it->second, pose, radius(id)) > updateError) {
      c.moved.push_back(id);
      c.target.emplace(id, pose);
    } else {
      c.target.emplace(id, it->second);
    }
  }
  return c;
}

}  // namespace rtabmap::maps_detail
