#include "rtabmap_core/geometry/IMU.h"

#include <cmath>

namespace rtabmap {

Transform baseOrientationFromImu(const IMU& imu) {
  if (!imu.hasOrientation()) return Transform();
  const Eigen::Quaterniond worldImu = imu.orientation.normalized();
  if (!std::isfinite(worldImu.w()) || !std::isfinite(worldImu.vec().norm())) return Transform();
  const Eigen::Quaterniond baseImu = imu.localTransform.isNull() ? Eigen::Quaterniond::Identity()
                                                                 : imu.localTransform.quaternion().normalized();
  const Eigen::Quaterniond worldBase = worldImu * baseImu.conjugate();
  return Transform(0.0, 0.0, 0.0, worldBase.x(), worldBase.y(), worldBase.z(), worldBase.w());
}

}  // namespace rtabmap
