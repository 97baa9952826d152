// Stages: segmented cloud -> 2D grid (projection, 2D ray tracing) or 3D grid (one point per voxel).
#include <algorithm>
#include <unordered_set>
#include <vector>

#include "Raster2D.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

using maps_detail::CellMean;
using maps_detail::cellCentre;
using maps_detail::cellIndex;
using maps_detail::cellKey;
using maps_detail::Raster2D;

namespace {

// Mean x y of the points of each cell, sorted by cell.
std::vector<CellMean> cellMeans(const Cloud& cloud, float c) {
  std::vector<CellMean> cells;
  cells.reserve(cloud.size());
  for (const cv::Point3f& p : cloud.points) {
    cells.push_back({cellKey(cellIndex(p.x, c), cellIndex(p.y, c)), p.x, p.y, 0.0f, 1});
  }
  std::sort(cells.begin(), cells.end(), [](const CellMean& a, const CellMean& b) { return a.key < b.key; });
  std::vector<CellMean> merged;
  for (const CellMean& m : cells) {
    if (!merged.empty() && merged.back().key == m.key) {
      merged.back().x += m.x;
      merged.back().y += m.y;
      ++merged.back().count;
    } else {
      merged.push_back(m);
    }
  }
  for (CellMean& m : merged) {
    m.x /= static_cast<float>(m.count);
    m.y /= static_cast<float>(m.count);
  }
  return merged;
}

cv::Mat toCells2D(const std::vector<cv::Vec2f>& v) {
  return v.empty() ? cv::Mat() : cv::Mat(v, true).reshape(2, 1);
}

}  // namespace

LocalGrid projectTo2D(const Cloud& ground, const Cloud& obstacles, float c) {
  LocalGrid grid;
  grid.cellSize = c;
  const std::vector<CellMean> obstacleCells = cellMeans(obstacles, c);
  std::unordered_set<int64_t> occupied;
  occupied.reserve(obstacleCells.size() * 2);
  std::vector<cv::Vec2f> obs, gnd;
  for (const CellMean& m : obstacleCells) {
    occupied.insert(m.key);
    obs.emplace_back(m.x, m.y);
  }
  for (const CellMean& m : cellMeans(ground, c)) {
    if (occupied.count(m.key)) continue;  // a cell with an obstacle is not traversable
    const int col = cellIndex(m.x, c), row = cellIndex(m.y, c);
    gnd.emplace_back(cellCentre(col, c), cellCentre(row, c));
  }
  grid.obstacles = toCells2D(obs);
  grid.ground = toCells2D(gnd);
  return grid;
}

void rayTrace2D(LocalGrid& grid, float rangeMax) {
  const float c = grid.cellSize;
  if (!(c > 0.0f)) return;
  const Cloud ground = cloudFromCells(grid.ground);
  const Cloud obstacles = cloudFromCells(grid.obstacles);
  if (ground.empty() && obstacles.empty()) return;
  const float vx = grid.viewPoint.x(), vy = grid.viewPoint.y();
  const int vc = cellIndex(vx, c), vr = cellIndex(vy, c);
  int minC = vc, maxC = vc, minR = vr, maxR = vr;
  auto extend = [&](const Cloud& cloud) {
    for (const cv::Point3f& p : cloud.points) {
      const int col = cellIndex(p.x, c), row = cellIndex(p.y, c);
      minC = std::min(minC, col); maxC = std::max(maxC, col);
      minR = std::min(minR, row); maxR = std::max(maxR, row);
    }
  };
  extend(ground);
  extend(obstacles);
  Raster2D raster(minC, minR, maxC, maxR);
  for (const cv::Point3f& p : obstacles.points) raster.set(cellIndex(p.x, c), cellIndex(p.y, c), Raster2D::kObstacle);
  for (const cv::Point3f& p : ground.points) raster.raise(cellIndex(p.x, c), cellIndex(p.y, c), Raster2D::kGround);
  // Rays go to the obstacle cells only, and stop at the first obstacle on their way: in a
  // projection, a cell behind an obstacle (under a box top, beyond a wall) was not seen empty,
  // whatever the 3D ray passed over. Ground cells are already known free.
  for (const cv::Point3f& p : obstacles.points) {
    float ex = p.x, ey = p.y;
    const float dx = ex - vx, dy = ey - vy;
    const float d = std::sqrt(dx * dx + dy * dy);
    if (rangeMax > 0.0f && d > rangeMax) {
      ex = vx + dx * rangeMax / d;
      ey = vy + dy * rangeMax / d;
    }
    raster.traceFree(vc, vr, cellIndex(ex, c), cellIndex(ey, c), false, true);
  }
  std::vector<cv::Vec2f> empty;
  for (int r = 0; r < raster.height(); ++r) {
    for (int col = 0; col < raster.width(); ++col) {
      if (raster.get(col + minC, r + minR) == Raster2D::kFree) {
        empty.emplace_back(cellCentre(col + minC, c), cellCentre(r + minR, c));
      }
    }
  }
  grid.empty = toCells2D(empty);
}

LocalGrid keep3D(const Cloud& ground, const Cloud& obstacles, float c) {
  LocalGrid grid;
  grid.cellSize = c;
  const Cloud obs = voxelFilter(obstacles, c);
  const Cloud gnd = voxelFilter(ground, c);
  // A voxel holding both keeps the obstacle.
  auto key = [c](const cv::Point3f& p) {
    const int64_t x = cellIndex(p.x, c) & 0x1fffff, y = cellIndex(p.y, c) & 0x1fffff,
                  z = cellIndex(p.z, c) & 0x1fffff;
    return (x << 42) | (y << 21) | z;
  };
  std::unordered_set<int64_t> occupied;
  occupied.reserve(obs.size() * 2);
  for (const cv::Point3f& p : obs.points) occupied.insert(key(p));
  Cloud groundOnly;
  groundOnly.reserve(gnd.size(), gnd.hasColors());
  for (size_t i = 0; i < gnd.size(); ++i) {
    if (occupied.count(key(gnd.points[i]))) continue;
    if (gnd.hasColors()) groundOnly.push_back(gnd.points[i], gnd.colors[i]);
    else groundOnly.push_back(gnd.points[i]);
  }
  grid.obstacles = cellsFromCloud(obs, false);
  grid.ground = cellsFromCloud(groundOnly, false);
  return grid;
}

}  // namespace rtabmap
