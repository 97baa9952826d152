// Stages on clouds without PCL: height limits, footprint removal, height segmentation.
#include <cmath>

#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

namespace {
template <typename Keep>
Cloud filtered(const Cloud& cloud, Keep keep) {
  Cloud out;
  const bool colours = cloud.hasColors();
  out.reserve(cloud.size(), colours);
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!keep(cloud.points[i])) continue;
    if (colours) out.push_back(cloud.points[i], cloud.colors[i]);
    else out.push_back(cloud.points[i]);
  }
  return out;
}
}  // namespace

Cloud cropHeights(const Cloud& cloud, float minZ, float maxZ) {
  if (minZ == 0.0f && maxZ == 0.0f) return cloud;
  return filtered(cloud, [&](const cv::Point3f& p) {
    return (minZ == 0.0f || p.z >= minZ) && (maxZ == 0.0f || p.z <= maxZ);
  });
}

Cloud removeFootprint(const Cloud& cloud, const LocalGridOptions& o, int* removed) {
  if (!o.hasFootprint()) {
    if (removed) *removed = 0;
    return cloud;
  }
  const float halfL = o.footprintLength / 2.0f;
  const float halfW = (o.footprintWidth > 0.0f ? o.footprintWidth : o.footprintLength) / 2.0f;
  Cloud out = filtered(cloud, [&](const cv::Point3f& p) {
    const bool inside = std::abs(p.x) <= halfL && std::abs(p.y) <= halfW &&
                        (o.footprintHeight <= 0.0f || p.z <= o.footprintHeight);
    return !inside;
  });
  if (removed) *removed = static_cast<int>(cloud.size() - out.size());
  return out;
}

GroundObstacles segmentGroundByHeight(const Cloud& cloud, const LocalGridOptions& o) {
  GroundObstacles out;
  out.ground = filtered(cloud, [&](const cv::Point3f& p) {
    return p.z <= o.maxGroundHeight && (o.minGroundHeight == 0.0f || p.z >= o.minGroundHeight);
  });
  out.obstacles = filtered(cloud, [&](const cv::Point3f& p) { return p.z > o.maxGroundHeight; });
  return out;
}

}  // namespace rtabmap
