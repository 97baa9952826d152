// Stage: 2D laser scan -> 2D local grid by ray tracing (see LocalGridStages.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "Raster2D.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

using maps_detail::CellMean;
using maps_detail::cellCentre;
using maps_detail::cellIndex;
using maps_detail::cellKey;
using maps_detail::Raster2D;

namespace {

struct Ray {
  float x, y;  // end point, base frame
  bool hit;    // an obstacle at the end (false: free up to the end, e.g. a max-range beam)
};

// Directions of the beams that came back empty, from the gaps between returned beams. The beam
// spacing is the median gap (most beams return on any real scan); the field of view is
// (maxPoints - 1) spacings, centred on the sensor's x axis.
std::vector<float> missingBeamAngles(std::vector<float> angles, int maxPoints) {
  std::vector<float> missing;
  if (angles.size() < 2) return missing;
  std::sort(angles.begin(), angles.end());
  std::vector<float> gaps;
  gaps.reserve(angles.size());
  for (size_t i = 1; i < angles.size(); ++i) {
    const float g = angles[i] - angles[i - 1];
    if (g > 1e-6f) gaps.push_back(g);
  }
  if (gaps.empty()) return missing;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const float inc = gaps[gaps.size() / 2];
  float start = angles.front(), end = angles.back();
  if (maxPoints > 1) {
    const float fov = std::min(inc * static_cast<float>(maxPoints - 1), static_cast<float>(2.0 * M_PI) - inc);
    start = std::min(start, -fov / 2.0f);
    end = std::max(end, fov / 2.0f);
  }
  angles.push_back(end + inc);  // sentinel: fills the gap up to the end of the field of view
  float previous = start - inc;
  for (float a : angles) {
    const int steps = static_cast<int>(std::lround((a - previous) / inc)) - 1;
    for (int k = 1; k <= steps; ++k) missing.push_back(previous + static_cast<float>(k) * inc);
    previous = a;
  }
  return missing;
}

}  // namespace

LocalGrid rayTraceScan2D(const LaserScan& scan, const LocalGridOptions& options,
                         ScanRayTracingStats* statsOut) {
  if (!scan.empty() && !scan.is2d()) {
    throw FormatError("2D ray tracing needs a planar scan; got a " +
                      LaserScan::formatName(scan.format()) + " scan (use the cloud path)");
  }
  ScanRayTracingStats stats;
  LocalGrid grid;
  grid.cellSize = options.cellSize;
  const Eigen::Isometry3f sensorToBase = scan.localTransform().toEigen().cast<float>();
  const Eigen::Vector3f viewPoint = sensorToBase.translation();
  grid.viewPoint = viewPoint;

  std::vector<Ray> rays;
  std::vector<float> angles;
  rays.reserve(scan.size());
  angles.reserve(scan.size());
  const int step = std::max(1, options.scanDecimation);
  for (int i = 0; i < scan.size(); i += step) {
    ++stats.beams;
    Eigen::Vector3f p = scan.point(i);
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) {
      ++stats.invalid;
      continue;
    }
    p.z() = 0.0f;
    const float range = p.norm();
    if (range < 1e-6f) {  // no direction: nothing to trace
      ++stats.invalid;
      continue;
    }
    if (options.rangeMin > 0.0f && range < options.rangeMin) {
      ++stats.belowRangeMin;
      continue;
    }
    angles.push_back(std::atan2(p.y(), p.x()));
    bool hit = true;
    if (options.rangeMax > 0.0f && range > options.rangeMax) {
      // Beyond the trusted range the hit is dropped but the beam still crossed free space.
      p *= options.rangeMax / range;
      hit = false;
      ++stats.beyondRangeMax;
    }
    const Eigen::Vector3f b = sensorToBase * p;
    rays.push_back({b.x(), b.y(), hit});
  }

  if (options.scan2dUnknownSpaceFilled) {
    const float fillRange =
        options.rangeMax > 0.0f ? options.rangeMax : static_cast<float>(scan.rangeMax());
    if (fillRange > 0.0f) {
      for (float a : missingBeamAngles(angles, scan.maxPoints())) {
        const Eigen::Vector3f b =
            sensorToBase * Eigen::Vector3f(fillRange * std::cos(a), fillRange * std::sin(a), 0.0f);
        rays.push_back({b.x(), b.y(), false});
        ++stats.unknownRaysFilled;
      }
    }
  }
  if (statsOut) *statsOut = stats;
  if (rays.empty()) return grid;

  const float c = options.cellSize;
  const int vc = cellIndex(viewPoint.x(), c), vr = cellIndex(viewPoint.y(), c);
  int minC = vc, maxC = vc, minR = vr, maxR = vr;
  for (const Ray& ray : rays) {
    const int ec = cellIndex(ray.x, c), er = cellIndex(ray.y, c);
    minC = std::min(minC, ec); maxC = std::max(maxC, ec);
    minR = std::min(minR, er); maxR = std::max(maxR, er);
  }
  Raster2D raster(minC, minR, maxC, maxR);

  // Obstacles first, so that no ray of this scan clears them.
  std::vector<CellMean> hits;
  hits.reserve(rays.size());
  for (const Ray& ray : rays) {
    if (!ray.hit) continue;
    const int ec = cellIndex(ray.x, c), er = cellIndex(ray.y, c);
    raster.set(ec, er, Raster2D::kObstacle);
    hits.push_back({cellKey(ec, er), ray.x, ray.y, 0.0f, 1});
  }
  for (const Ray& ray : rays) {
    raster.traceFree(vc, vr, cellIndex(ray.x, c), cellIndex(ray.y, c), !ray.hit);
  }

  // Obstacles: the mean of the hits of each cell.
  std::sort(hits.begin(), hits.end(), [](const CellMean& a, const CellMean& b) { return a.key < b.key; });
  std::vector<cv::Vec2f> obstacles;
  for (size_t i = 0; i < hits.size();) {
    size_t j = i;
    float sx = 0.f, sy = 0.f;
    for (; j < hits.size() && hits[j].key == hits[i].key; ++j) {
      sx += hits[j].x;
      sy += hits[j].y;
    }
    const float n = static_cast<float>(j - i);
    obstacles.emplace_back(sx / n, sy / n);
    i = j;
  }
  std::vector<cv::Vec2f> empty;
  for (int r = 0; r < raster.height(); ++r) {
    for (int col = 0; col < raster.width(); ++col) {
      if (raster.get(col + raster.minCol(), r + raster.minRow()) == Raster2D::kFree) {
        empty.emplace_back(cellCentre(col + raster.minCol(), c), cellCentre(r + raster.minRow(), c));
      }
    }
  }
  if (!obstacles.empty()) grid.obstacles = cv::Mat(obstacles, true).reshape(2, 1);
  if (!empty.empty()) grid.empty = cv::Mat(empty, true).reshape(2, 1);
  return grid;
}

}  // namespace rtabmap
