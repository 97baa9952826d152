#include "rtabmap_conversions/LandmarkConversions.h"

#include "Support.h"
#include "rtabmap_conversions/OdometryConversions.h"
#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

std::optional<rtabmap::Landmark> landmarkFromMsg(const rtabmap_ros::LandmarkDetection& msg, double linearVariance,
                                                 double angularVariance, std::string* error) {
  const std::string what = "landmark " + std::to_string(msg.id);
  if (msg.id < 1) return detail::fail(error, what + ": ids start at 1 (its graph node is -id)");
  if (msg.header.frame_id.empty()) return detail::fail(error, what + ": empty header.frame_id");
  const geometry_msgs::Pose& p = msg.pose.pose;
  const double values[] = {p.position.x,    p.position.y,    p.position.z,   p.orientation.x,
                           p.orientation.y, p.orientation.z, p.orientation.w};
  if (!detail::allFinite(values)) return detail::fail(error, what + ": NaN or infinite pose");
  const double q2 = p.orientation.x * p.orientation.x + p.orientation.y * p.orientation.y +
                    p.orientation.z * p.orientation.z + p.orientation.w * p.orientation.w;
  if (q2 < 1e-12) return detail::fail(error, what + ": zero-length orientation quaternion");
  if (!std::isfinite(msg.size) || msg.size < 0.0f) return detail::fail(error, what + ": negative or non-finite size");
  if (!detail::allFinite(msg.pose.covariance)) return detail::fail(error, what + ": NaN or infinite covariance");
  rtabmap::Landmark l;
  l.id = msg.id;
  l.size = msg.size;
  l.pose = transformFromPoseMsg(p);
  l.covariance = covarianceFromMsg(msg.pose.covariance);
  if (l.covariance.isZero()) {
    l.covariance.diagonal() << linearVariance, linearVariance, linearVariance, angularVariance, angularVariance,
        angularVariance;
  }
  if (l.covariance.diagonal().minCoeff() <= 0.0) {
    return detail::fail(error, what + ": covariance with a non-positive diagonal");
  }
  return l;
}

}  // namespace rtabmap_conversions
