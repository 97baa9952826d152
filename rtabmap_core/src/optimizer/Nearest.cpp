// graph:: nearest nodes and nodes in a radius (linear scans: graphs of Working Memory hold
// thousands of nodes, where a scan costs microseconds and needs no index to maintain).
#include <algorithm>
#include <cmath>

#include "rtabmap_core/optimizer/Graph.h"
#include "PoseMath.h"

namespace rtabmap::graph {

double poseDistance(const Transform& a, const Transform& b, bool is2D) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y();
  const double dz = is2D ? 0.0 : a.z() - b.z();
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

std::vector<std::pair<int, double>> findNearestNodes(const Poses& poses, const Transform& target,
                                                      int k, bool is2D) {
  std::vector<std::pair<int, double>> all;
  if (k <= 0 || target.isNull()) return all;
  all.reserve(poses.size());
  for (const auto& [id, pose] : poses) {
    if (!pose.isNull()) all.emplace_back(id, poseDistance(pose, target, is2D));
  }
  const auto closer = [](const std::pair<int, double>& a, const std::pair<int, double>& b) {
    return a.second < b.second || (a.second == b.second && a.first < b.first);
  };
  const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(k), all.size());
  std::partial_sort(all.begin(), all.begin() + n, all.end(), closer);
  all.resize(n);
  return all;
}

int findNearestNode(const Poses& poses, const Transform& target, double* distance, bool is2D) {
  const auto nearest = findNearestNodes(poses, target, 1, is2D);
  if (nearest.empty()) return 0;
  if (distance) *distance = nearest.front().second;
  return nearest.front().first;
}

std::map<int, double> findNodesInRadius(const Poses& poses, const Transform& target, double radius,
                                        bool is2D, double maxAngle) {
  std::map<int, double> out;
  if (target.isNull() || radius < 0.0) return out;
  for (const auto& [id, pose] : poses) {
    if (pose.isNull()) continue;
    const double d = poseDistance(pose, target, is2D);
    if (d > radius) continue;
    if (maxAngle > 0.0) {
      const double angle =
          is2D ? std::fabs(optimizer_internal::wrapAngle(pose.yaw() - target.yaw()))
               : (target.inverse() * pose).getAngle();
      if (angle > maxAngle) continue;
    }
    out.emplace(id, d);
  }
  return out;
}

}  // namespace rtabmap::graph
