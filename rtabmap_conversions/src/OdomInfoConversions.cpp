#include "rtabmap_conversions/OdomInfoConversions.h"

#include "Support.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

rtabmap_ros::OdomInfo odomInfoToMsg(const rtabmap::OdometryInfo& info, rtabmap::Odometry::Type type,
                                    const std_msgs::Header& header) {
  rtabmap_ros::OdomInfo msg;
  msg.header = header;
  msg.lost = info.lost;
  msg.matches = info.reg.matches;
  msg.inliers = info.reg.inliers;
  msg.icpInliersRatio = static_cast<float>(info.reg.icpInliersRatio);
  msg.icpRotation = static_cast<float>(info.reg.icpRotation);
  msg.icpTranslation = static_cast<float>(info.reg.icpTranslation);
  msg.icpStructuralComplexity = static_cast<float>(info.reg.icpStructuralComplexity);
  msg.icpStructuralDistribution = static_cast<float>(info.reg.icpStructuralDistribution);
  msg.icpCorrespondences = info.reg.icpCorrespondences;
  msg.covariance = covarianceToMsg(info.covariance);
  msg.features = info.features;
  msg.localMapSize = info.localMapSize;
  msg.localScanMapSize = info.localScanMapSize;
  msg.localKeyFrames = info.localKeyFrames;
  msg.keyFrameAdded = info.keyFrameAdded;
  msg.timeEstimation = static_cast<float>(info.timeEstimationMs / 1000.0);
  msg.stamp = static_cast<float>(info.stamp);
  msg.interval = static_cast<float>(info.interval);
  msg.distanceTravelled = static_cast<float>(info.distanceTravelled);
  const bool frameToFrame = type == rtabmap::Odometry::Type::kF2F || type == rtabmap::Odometry::Type::kS2S;
  msg.type = frameToFrame ? 1 : 0;
  msg.wordMatches.assign(info.reg.matchesIDs.begin(), info.reg.matchesIDs.end());
  msg.wordInliers.assign(info.reg.inliersIDs.begin(), info.reg.inliersIDs.end());
  msg.transform = transformToMsg(info.transform);
  msg.transformFiltered = transformToMsg(info.transform);
  msg.guessVelocity = transformToMsg(info.guess);
  return msg;
}

std::optional<rtabmap::OdometryInfo> odomInfoFromMsg(const rtabmap_ros::OdomInfo& msg, std::string* error) {
  if (!detail::allFinite(msg.covariance)) return detail::fail(error, "OdomInfo has a NaN or infinite covariance");
  rtabmap::OdometryInfo info;
  info.lost = msg.lost;
  info.reg.success = !msg.lost;
  info.reg.matches = msg.matches;
  info.reg.inliers = msg.inliers;
  info.reg.icpInliersRatio = msg.icpInliersRatio;
  info.reg.icpRotation = msg.icpRotation;
  info.reg.icpTranslation = msg.icpTranslation;
  info.reg.icpStructuralComplexity = msg.icpStructuralComplexity;
  info.reg.icpStructuralDistribution = msg.icpStructuralDistribution;
  info.reg.icpCorrespondences = msg.icpCorrespondences;
  info.reg.matchesIDs.assign(msg.wordMatches.begin(), msg.wordMatches.end());
  info.reg.inliersIDs.assign(msg.wordInliers.begin(), msg.wordInliers.end());
  info.covariance = covarianceFromMsg(msg.covariance);
  info.reg.covariance = info.covariance;
  info.features = msg.features;
  info.localMapSize = msg.localMapSize;
  info.localScanMapSize = msg.localScanMapSize;
  info.localKeyFrames = msg.localKeyFrames;
  info.keyFrameAdded = msg.keyFrameAdded;
  info.timeEstimationMs = static_cast<double>(msg.timeEstimation) * 1000.0;
  // The float32 `stamp` field cannot hold a Unix time to the second: the header has it exactly.
  info.stamp = msg.header.stamp.isZero() ? double(msg.stamp) : msg.header.stamp.toSec();
  info.interval = msg.interval;
  info.distanceTravelled = msg.distanceTravelled;
  info.transform = transformFromMsg(msg.transform);
  info.guess = transformFromMsg(msg.guessVelocity);
  return info;
}

}  // namespace rtabmap_conversions
