#include "rtabmap_conversions/ImuConversions.h"

#include "Support.h"

namespace rtabmap_conversions {

namespace {

void toArray(const Eigen::Matrix3d& m, boost::array<double, 9>& out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[size_t(r * 3 + c)] = m(r, c);
  }
}

Eigen::Matrix3d fromArray(const boost::array<double, 9>& in) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = in[size_t(r * 3 + c)];
  }
  return m;
}

}  // namespace

sensor_msgs::Imu imuToMsg(const rtabmap::IMU& imu, const std_msgs::Header& header) {
  sensor_msgs::Imu msg;
  msg.header = header;
  if (imu.hasOrientation()) {
    const Eigen::Quaterniond q = imu.orientation.normalized();
    msg.orientation.x = q.x();
    msg.orientation.y = q.y();
    msg.orientation.z = q.z();
    msg.orientation.w = q.w();
    toArray(imu.orientationCovariance, msg.orientation_covariance);
  } else {
    msg.orientation.w = 0.0;  // explicit: no orientation
    msg.orientation_covariance.fill(0.0);
    msg.orientation_covariance[0] = -1.0;
  }
  msg.angular_velocity.x = imu.angularVelocity.x();
  msg.angular_velocity.y = imu.angularVelocity.y();
  msg.angular_velocity.z = imu.angularVelocity.z();
  toArray(imu.angularVelocityCovariance, msg.angular_velocity_covariance);
  msg.linear_acceleration.x = imu.linearAcceleration.x();
  msg.linear_acceleration.y = imu.linearAcceleration.y();
  msg.linear_acceleration.z = imu.linearAcceleration.z();
  toArray(imu.linearAccelerationCovariance, msg.linear_acceleration_covariance);
  return msg;
}

std::optional<rtabmap::IMU> imuFromMsg(const sensor_msgs::Imu& msg, const rtabmap::Transform& localTransform,
                                       std::string* error) {
  const std::string what = "Imu of frame '" + msg.header.frame_id + "'";
  const double motion[] = {msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z,
                           msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z};
  if (!detail::allFinite(motion) || !detail::allFinite(msg.angular_velocity_covariance) ||
      !detail::allFinite(msg.linear_acceleration_covariance)) {
    return detail::fail(error, what + " has NaN or infinite angular velocity, acceleration or covariance");
  }
  rtabmap::IMU imu;
  imu.localTransform = localTransform;
  imu.angularVelocity = Eigen::Vector3d(motion[0], motion[1], motion[2]);
  imu.linearAcceleration = Eigen::Vector3d(motion[3], motion[4], motion[5]);
  imu.angularVelocityCovariance = fromArray(msg.angular_velocity_covariance);
  imu.linearAccelerationCovariance = fromArray(msg.linear_acceleration_covariance);
  if (msg.orientation_covariance[0] == -1.0) return imu;  // no orientation, by the message's own rule
  const auto& o = msg.orientation;
  const double q[] = {o.x, o.y, o.z, o.w};
  if (!detail::allFinite(q) || !detail::allFinite(msg.orientation_covariance)) {
    return detail::fail(error, what + " has a NaN or infinite orientation or orientation covariance");
  }
  const Eigen::Quaterniond quat(o.w, o.x, o.y, o.z);
  // Some drivers leave the quaternion all zero without setting the -1 marker: no orientation
  // either (normalising it would invent one).
  if (quat.norm() < 1e-6) return imu;
  imu.orientation = quat.normalized();
  imu.orientationCovariance = fromArray(msg.orientation_covariance);
  return imu;
}

}  // namespace rtabmap_conversions
