#include "ScanMerge.h"

#include <opencv2/core.hpp>

#include <algorithm>

namespace rtabmap {

LaserScan mergeScans(const std::vector<std::pair<LaserScan, Transform>>& parts) {
  if (parts.empty()) return LaserScan();
  const LaserScan::Format format = parts.front().first.format();
  const int channels = LaserScan::channels(format);
  const bool is2d = LaserScan::is2d(format);
  const bool normals = LaserScan::hasNormals(format);
  int total = 0, maxPoints = 0;
  double rangeMax = 0.0;
  for (const auto& [scan, pose] : parts) {
    if (scan.format() != format || pose.isNull()) continue;
    total += scan.size();
    maxPoints += std::max(scan.maxPoints(), scan.size());
    rangeMax = std::max(rangeMax, scan.rangeMax());
  }
  if (total == 0) return LaserScan();
  cv::Mat out(1, total, CV_32FC(channels));
  int k = 0;
  for (const auto& [scan, pose] : parts) {
    if (scan.format() != format || pose.isNull() || scan.empty()) continue;
    const LaserScan base = scan.transformedToBase();
    const Eigen::Matrix3f r = pose.rotationMatrix().cast<float>();
    const Eigen::Vector3f t = pose.translation().cast<float>();
    for (int i = 0; i < base.size(); ++i, ++k) {
      const float* src = base.data().ptr<float>(0, i);
      float* dst = out.ptr<float>(0, k);
      std::copy(src, src + channels, dst);
      const Eigen::Vector3f p = r * Eigen::Vector3f(src[0], src[1], is2d ? 0.f : src[2]) + t;
      dst[0] = p.x();
      dst[1] = p.y();
      if (!is2d) dst[2] = p.z();
      if (normals) {
        const int n0 = channels - 3;
        const Eigen::Vector3f n = r * Eigen::Vector3f(src[n0], src[n0 + 1], src[n0 + 2]);
        dst[n0] = n.x();
        dst[n0 + 1] = n.y();
        dst[n0 + 2] = n.z();
      }
    }
  }
  // Range limits are the sensor's; the merged points are no longer ranges from one origin.
  return LaserScan(out, maxPoints, 0.0, 0.0, format);
}

}  // namespace rtabmap
