#include "GyroIntegration.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace rtabmap::odometry_detail {
namespace {

Eigen::Matrix3d exponential(const Eigen::Vector3d& rotationVector) {
  const double angle = rotationVector.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotationVector / angle).toRotationMatrix();
}

}  // namespace

bool GyroIntegration::add(double stamp, const IMU& imu) {
  if (!std::isfinite(stamp) || !imu.angularVelocity.allFinite() || imu.angularVelocity.isZero(0.0)) return false;
  if (!samples_.empty() && stamp <= samples_.back().stamp) return false;
  const Eigen::Matrix3d baseImu =
      imu.localTransform.isNull() ? Eigen::Matrix3d::Identity() : imu.localTransform.rotationMatrix();
  samples_.push_back({stamp, baseImu * imu.angularVelocity});
  while (samples_.front().stamp < stamp - keep_) samples_.pop_front();
  return true;
}

std::optional<Eigen::Matrix3d> GyroIntegration::rotationBetween(double t0, double t1) const {
  if (samples_.empty() || !(t1 > t0)) return std::nullopt;
  if (samples_.front().stamp > t0 + maxGap_ || samples_.back().stamp < t1 - maxGap_) return std::nullopt;
  // Piecewise: before the first sample and after the last one, their own rate; between two,
  // their mean. Each piece is clipped to [t0, t1] and turns the base in its current frame.
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  auto turn = [&](double a, double b, const Eigen::Vector3d& w) {
    a = std::max(a, t0);
    b = std::min(b, t1);
    if (b > a) r = r * exponential(w * (b - a));
  };
  turn(t0, samples_.front().stamp, samples_.front().angularVelocity);
  for (size_t i = 1; i < samples_.size(); ++i) {
    const Sample& p = samples_[i - 1];
    const Sample& q = samples_[i];
    if (q.stamp <= t0 || p.stamp >= t1) continue;
    if (q.stamp - p.stamp > maxGap_) {
      // A hole: only its part within [t0, t1] matters; at either end, a short part is covered
      // by the sample on the inside, as the first and last samples are.
      const double a = std::max(p.stamp, t0), b = std::min(q.stamp, t1);
      if (b - a > maxGap_) return std::nullopt;
      turn(a, b, p.stamp < t0 ? q.angularVelocity : p.angularVelocity);
      continue;
    }
    turn(p.stamp, q.stamp, 0.5 * (p.angularVelocity + q.angularVelocity));
  }
  turn(samples_.back().stamp, t1, samples_.back().angularVelocity);
  return r;
}

void GyroIntegration::dropBefore(double t) {
  // Keep the last sample at or before t: it covers the start of the next integration.
  while (samples_.size() > 1 && samples_[1].stamp <= t) samples_.pop_front();
}

}  // namespace rtabmap::odometry_detail
