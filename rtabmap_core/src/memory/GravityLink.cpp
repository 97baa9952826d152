#include "rtabmap_core/memory/GravityLink.h"

#include <cmath>

namespace rtabmap::memory {

Transform baseOrientationFromImu(const IMU& imu) {
  if (!imu.hasOrientation()) return Transform();
  const Eigen::Quaterniond worldImu = imu.orientation.normalized();
  if (!std::isfinite(worldImu.w()) || !std::isfinite(worldImu.vec().norm())) return Transform();
  const Eigen::Quaterniond baseImu = imu.localTransform.isNull() ? Eigen::Quaterniond::Identity()
                                                                 : imu.localTransform.quaternion().normalized();
  const Eigen::Quaterniond worldBase = worldImu * baseImu.conjugate();
  return Transform(0.0, 0.0, 0.0, worldBase.x(), worldBase.y(), worldBase.z(), worldBase.w());
}

std::optional<Link> gravityLinkOf(int id, const Transform& odomPose, const IMU& imu, bool useOdomGravity) {
  if (odomPose.isNull() || odomPose.isInvalid()) return std::nullopt;
  // Only the rotation is a measurement of gravity; the translation would mean nothing.
  const Eigen::Quaterniond q = odomPose.quaternion().normalized();
  const Transform orientation = useOdomGravity ? Transform(0.0, 0.0, 0.0, q.x(), q.y(), q.z(), q.w())
                                               : baseOrientationFromImu(imu);
  if (orientation.isNull()) return std::nullopt;
  return Link(id, id, Link::kGravity, orientation);
}

}  // namespace rtabmap::memory
