#include "GroundTruthError.h"

#include <cmath>
#include <vector>

namespace rtabmap {

std::optional<GroundTruthErrors> groundTruthErrors(const std::map<int, Transform>& poses,
                                                   const std::map<int, Transform>& groundTruth) {
  std::vector<int> ids;
  std::vector<Eigen::Vector3d> estimated, truth;
  for (const auto& [id, pose] : poses) {
    const auto gt = groundTruth.find(id);
    if (gt == groundTruth.end() || gt->second.isNull() || pose.isNull()) continue;
    ids.push_back(id);
    estimated.push_back(pose.translation());
    truth.push_back(gt->second.translation());
  }
  if (ids.size() < 3) return std::nullopt;
  const Transform alignment = alignPoints(estimated, truth, false);
  std::vector<double> metres, degrees;
  for (int id : ids) {
    const Transform error = groundTruth.at(id).inverse() * (alignment * poses.at(id));
    metres.push_back(error.translation().norm());
    degrees.push_back(std::fabs(error.getAngle()) * 180.0 / M_PI);
  }
  return GroundTruthErrors{computeErrorStats(metres), computeErrorStats(degrees)};
}

}  // namespace rtabmap
