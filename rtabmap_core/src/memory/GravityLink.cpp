#include "rtabmap_core/memory/GravityLink.h"

namespace rtabmap::memory {

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
