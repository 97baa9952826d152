#include "rtabmap_core/sim/WheelOdometry.h"

#include <cmath>

namespace rtabmap::sim {

WheelOdometry::WheelOdometry(const OdometryNoise& noise, uint64_t seed, int consumers)
    : noise_(noise), rng_(seed, "odometry"), increments_(static_cast<size_t>(std::max(1, consumers))) {}

void WheelOdometry::reset(const Pose2& truePose) {
  lastTrue_ = truePose;
  pose_ = Pose2();
  for (auto& inc : increments_) inc = OdometryIncrement();
}

void WheelOdometry::update(const Pose2& truePose) {
  const Pose2 delta = lastTrue_.inverse() * truePose;
  lastTrue_ = truePose;
  const double travelled = std::hypot(delta.x, delta.y);
  const double forward = delta.x >= 0.0 ? 1.0 : -1.0;
  const double ds = forward * travelled;
  const double dyaw = delta.yaw;
  const double varS = noise_.translation * noise_.translation * travelled;
  const double varYaw = noise_.rotation * noise_.rotation * std::fabs(dyaw) +
                        noise_.rotationPerMetre * noise_.rotationPerMetre * travelled;
  Pose2 measured = delta;
  if (varS > 0.0 || varYaw > 0.0 || noise_.scaleBias != 0.0 || noise_.yawBiasPerMetre != 0.0) {
    const double dsNoisy = ds * (1.0 + noise_.scaleBias) + (varS > 0.0 ? std::sqrt(varS) * rng_.normal() : 0.0);
    const double yawError = noise_.yawBiasPerMetre * travelled + (varYaw > 0.0 ? std::sqrt(varYaw) * rng_.normal() : 0.0);
    // Same direction of travel as the truth, turned by half the heading error (an arc).
    const double scale = travelled > 1e-15 ? dsNoisy / ds : 0.0;
    const double c = std::cos(0.5 * yawError), s = std::sin(0.5 * yawError);
    if (travelled > 1e-15) {
      measured.x = scale * (c * delta.x - s * delta.y);
      measured.y = scale * (s * delta.x + c * delta.y);
    } else {
      measured.x = dsNoisy;
      measured.y = 0.0;
    }
    measured.yaw = Pose2::normalizeAngle(delta.yaw + yawError);
  }
  pose_ = pose_ * measured;

  // First-order covariance of the increment in (x, y, yaw), from (ds, dyaw) noise.
  const double half = 0.5 * measured.yaw;
  Eigen::Matrix<double, 3, 2> g;
  g << std::cos(half), -0.5 * ds * std::sin(half), std::sin(half), 0.5 * ds * std::cos(half), 0.0, 1.0;
  const Eigen::Matrix3d q = g * Eigen::Vector2d(varS, varYaw).asDiagonal() * g.transpose();
  for (auto& inc : increments_) {
    const double c = std::cos(inc.motion.yaw), s = std::sin(inc.motion.yaw);
    Eigen::Matrix3d jPrev = Eigen::Matrix3d::Identity();
    jPrev(0, 2) = -s * measured.x - c * measured.y;
    jPrev(1, 2) = c * measured.x - s * measured.y;
    Eigen::Matrix3d jInc = Eigen::Matrix3d::Identity();
    jInc(0, 0) = c;
    jInc(0, 1) = -s;
    jInc(1, 0) = s;
    jInc(1, 1) = c;
    inc.covariance = jPrev * inc.covariance * jPrev.transpose() + jInc * q * jInc.transpose();
    inc.motion = inc.motion * measured;
  }
}

OdometryIncrement WheelOdometry::take(int consumer) {
  OdometryIncrement& inc = increments_.at(static_cast<size_t>(consumer));
  OdometryIncrement out = inc;
  inc = OdometryIncrement();
  return out;
}

}  // namespace rtabmap::sim
