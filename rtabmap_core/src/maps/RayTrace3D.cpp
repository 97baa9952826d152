// Stage: 3D ray tracing of a 3D local grid through OctoMap's ray casting (see LocalGridStages.h).
#include <octomap/OcTree.h>

#include <vector>

#include "RayCaster.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

void rayTrace3D(LocalGrid& grid, float rangeMax) {
  if (!(grid.cellSize > 0.0f)) return;
  const Cloud ground = cloudFromCells(grid.ground);
  const Cloud obstacles = cloudFromCells(grid.obstacles);
  if (ground.empty() && obstacles.empty()) return;
  // The tree only provides OctoMap's key lattice and ray casting; nothing is inserted.
  octomap::OcTree lattice(grid.cellSize);
  std::vector<octomap::point3d> ends;
  std::vector<octomap::OcTreeKey> occupied;
  ends.reserve(ground.size() + obstacles.size());
  occupied.reserve(ends.capacity());
  for (const Cloud* cloud : {&obstacles, &ground}) {
    for (const cv::Point3f& p : cloud->points) {
      const octomap::point3d e(p.x, p.y, p.z);
      octomap::OcTreeKey k;
      if (!lattice.coordToKeyChecked(e, k)) continue;
      ends.push_back(e);
      occupied.push_back(k);
    }
  }
  const octomap::point3d origin(grid.viewPoint.x(), grid.viewPoint.y(), grid.viewPoint.z());
  std::vector<octomap::OcTreeKey> free;
  maps_detail::RayCaster caster;
  caster.cast(lattice, origin, ends, occupied, rangeMax, free);
  if (free.empty()) {
    grid.empty = cv::Mat();
    return;
  }
  cv::Mat cells(1, static_cast<int>(free.size()), CV_32FC3);
  auto* out = cells.ptr<cv::Vec3f>();
  for (size_t i = 0; i < free.size(); ++i) {
    const octomap::point3d c = lattice.keyToCoord(free[i]);
    out[i] = cv::Vec3f(c.x(), c.y(), c.z());
  }
  grid.empty = cells;
}

}  // namespace rtabmap
