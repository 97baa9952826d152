#pragma once
// One IMU sample (sensor_msgs/Imu): orientation (null-quaternion if unknown), angular velocity,
// linear acceleration, their 3x3 covariances, and the transform base -> IMU frame.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

struct IMU {
  Eigen::Quaterniond orientation{0, 0, 0, 0};  // w = x = y = z = 0: unknown
  Eigen::Matrix3d orientationCovariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();  // rad/s
  Eigen::Matrix3d angularVelocityCovariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d linearAcceleration = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Matrix3d linearAccelerationCovariance = Eigen::Matrix3d::Zero();
  Transform localTransform = Transform::Identity();

  bool empty() const { return angularVelocity.isZero() && linearAcceleration.isZero() && !hasOrientation(); }
  bool hasOrientation() const { return orientation.coeffs().squaredNorm() > 0.0; }
};

// The base's orientation in the IMU's gravity-aligned frame: R_world_imu * R_base_imu^-1
// (IMU::localTransform is the IMU's pose on the base). Null when the IMU has no orientation
// (or a non-finite one).
Transform baseOrientationFromImu(const IMU& imu);

}  // namespace rtabmap
